"""Start a set of nodes as separate processes, watch them, stop them cleanly.

Every node runs as ``sys.executable -m motoflex_ros.nodes.<module> --ros-args --params-file
<params>`` (the same interpreter, so the ROS wheels' bootstrap carries over) with its own
``ROS_DOMAIN_ID``, DDS on loopback (:mod:`.dds`) and ``ROS_LOG_DIR``; stdout and
stderr go to ``<log_dir>/<node>.log``. Processes are ended by their own pid only: SIGINT, then
SIGTERM, then SIGKILL after a grace period each.
"""
import os
import signal
import subprocess
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

import yaml

from motoflex_ros.errors import MotoflexError
from motoflex_ros.launcher.dds import configure_dds

__all__ = ["NodeSpec", "NodeGraph", "NodeDied", "ros_env", "describe_exit"]


class NodeDied(MotoflexError):
    """A node process ended while the run needed it."""


@dataclass(frozen=True)
class NodeSpec:
    """One node process: ``name`` (node and executable name), its parameters, and the module
    (default ``motoflex_ros.nodes.<name>``).
    """

    name: str
    params: dict = field(default_factory=dict)
    module: str = ""

    @property
    def module_name(self):
        """Python module run with ``-m``."""
        return self.module or f"motoflex_ros.nodes.{self.name}"


def ros_env(domain_id, log_dir, base=None):
    """Environment of a node process: own domain, DDS on loopback (unless MOTOFLEX_DDS says
    otherwise, see :mod:`.dds`), logs in ``log_dir``."""
    env = dict(os.environ if base is None else base)
    env.update(ROS_DOMAIN_ID=str(domain_id), ROS_LOG_DIR=str(log_dir), OPENBLAS_NUM_THREADS="1",
               PYTHONUNBUFFERED="1",
               MOTOFLEX_PARENT_PID=str(os.getpid()))   # nodes stop if the launcher dies
    configure_dds(env)
    return env


def describe_exit(code):
    """'exit 2' or 'killed by SIGKILL' for a Popen return code."""
    if code is not None and code < 0:
        return f"killed by {signal.Signals(-code).name}"
    return f"exit {code}"


class NodeGraph:
    """The processes of one run. Use as a context manager: leaving it stops every node."""

    def __init__(self, specs, domain_id, work_dir):
        self.specs = tuple(specs)
        self.domain_id = domain_id
        self.work_dir = Path(work_dir)
        self.log_dir = self.work_dir / "log"
        self.procs = {}

    def start(self):
        """Write each node's params file and start its process."""
        params_dir = self.work_dir / "params"
        params_dir.mkdir(parents=True, exist_ok=True)
        self.log_dir.mkdir(parents=True, exist_ok=True)
        env = ros_env(self.domain_id, self.log_dir)
        for spec in self.specs:
            params_file = params_dir / f"{spec.name}.yaml"
            params = {k: list(v) if isinstance(v, tuple) else v for k, v in spec.params.items()}
            params_file.write_text(yaml.safe_dump({spec.name: {"ros__parameters": params}}))
            cmd = [sys.executable, "-m", spec.module_name, "--ros-args",
                   "-r", f"__node:={spec.name}", "--params-file", str(params_file)]
            with open(self.log_dir / f"{spec.name}.log", "wb") as log:
                self.procs[spec.name] = subprocess.Popen(
                    cmd, env=env, stdout=log, stderr=subprocess.STDOUT,
                    stdin=subprocess.DEVNULL, start_new_session=True)
        return self

    def exited(self):
        """{name: return code} of the processes that have ended."""
        return {n: p.returncode for n, p in self.procs.items() if p.poll() is not None}

    def check_alive(self, allowed=()):
        """Raise NodeDied naming the first node that ended (except those in ``allowed``)."""
        for name, code in self.exited().items():
            if name not in allowed:
                raise NodeDied(f"node '{name}' died ({describe_exit(code)}); its log: "
                               f"{self.log_dir / (name + '.log')}: {self.log_tail(name)}")

    def log_tail(self, name, lines=3):
        """Last lines of a node's log, on one line."""
        path = self.log_dir / f"{name}.log"
        text = path.read_text(errors="replace").strip().splitlines() if path.exists() else []
        return " | ".join(text[-lines:]) or "(empty)"

    def wait(self, name, timeout):
        """Wait up to ``timeout`` [s] for node ``name`` to end; its return code or None."""
        try:
            return self.procs[name].wait(timeout)
        except subprocess.TimeoutExpired:
            return None

    def stop(self, grace=5.0):
        """SIGINT every live node, then SIGTERM, then SIGKILL; returns {name: return code}."""
        for sig in (signal.SIGINT, signal.SIGTERM, signal.SIGKILL):
            alive = [p for p in self.procs.values() if p.poll() is None]
            if not alive:
                break
            for proc in alive:
                try:
                    os.kill(proc.pid, sig)
                except ProcessLookupError:
                    pass
            deadline = time.monotonic() + grace
            for proc in alive:
                try:
                    proc.wait(max(0.0, deadline - time.monotonic()))
                except subprocess.TimeoutExpired:
                    pass
        return {n: p.returncode for n, p in self.procs.items()}

    def __enter__(self):
        return self.start()

    def __exit__(self, *exc):
        self.stop()
