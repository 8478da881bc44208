"""Start a set of nodes as separate processes, watch them, stop them cleanly.

Every node runs as ``sys.executable -m motoflex_ros.nodes.<module> --ros-args --params-file
<params>`` (the same interpreter, so the ROS wheels' bootstrap carries over) with its own
``ROS_DOMAIN_ID``, DDS on loopback (:mod:`.dds`), ``ROS_LOG_DIR`` and, for a rig in a
namespace, ``-r __ns:=<namespace>`` (its topics are relative: all of them move under it; /clock,
which rclpy's time source reads, is remapped to <namespace>/clock); stdout and
stderr go to ``<log_dir>/<node>.log``. The nodes write their publishers' GIDs to
``<work_dir>/endpoints`` and accept messages only from those
(:mod:`motoflex_ros.nodes.endpoints`). The run's inputs are pinned: the SHA-256 of every input
the launcher read and of every params file it wrote go to ``<work_dir>/input_pins.json``,
named in ``MOTOFLEX_INPUT_PINS`` for the nodes (:mod:`motoflex_ros.input_pins`). Processes are
ended by their own pid only: SIGINT, then SIGTERM, then SIGKILL after a grace period each.
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
from motoflex_ros.input_pins import PINS_ENV, sha256_bytes, write_pins
from motoflex_ros.nodes.dds import configure_dds
from motoflex_ros.nodes.endpoints import ENDPOINTS_ENV

__all__ = ["NodeSpec", "NodeGraph", "NodeDied", "ros_env", "describe_exit", "namespace_args",
           "node_key"]


class NodeDied(MotoflexError):
    """A node process ended while the run needed it."""


STOPPED_LIMIT_S = 5.0
"""How long a node's process may stay stopped (SIGSTOP, a debugger: state T) before the run
fails naming it [s]; the other nodes' stall timeouts (30 s) would otherwise name the node that
waits for it, not the one that stalled."""


def process_state(pid):
    """The state letter of process ``pid`` (R, S, D, T stopped, t traced, Z...), or None."""
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return None
    return stat.rsplit(")", 1)[1].split()[0]


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


def namespace_args(namespace):
    """ROS arguments that put a node in ``namespace`` ('/rig_a'; none for '/')."""
    namespace = "/" + namespace.strip("/")
    if namespace == "/":
        return []
    return ["-r", f"__ns:={namespace}", "-r", f"/clock:={namespace}/clock"]


def node_key(namespace, name):
    """The section of a params file for node ``name`` in ``namespace`` ('/rig_a/recorder')."""
    namespace = namespace.strip("/")
    return f"/{namespace}/{name}" if namespace else name


def describe_exit(code):
    """'exit 2', 'exit 143: stopped by SIGTERM' or 'killed by SIGKILL' for a Popen return
    code."""
    if code is not None and code < 0:
        return f"killed by {signal.Signals(-code).name}"
    if code in (128 + signal.SIGINT, 128 + signal.SIGTERM):
        return f"exit {code}: stopped by {signal.Signals(code - 128).name}"
    return f"exit {code}"


class NodeGraph:
    """The processes of one run. Use as a context manager: leaving it stops every node."""

    def __init__(self, specs, domain_id, work_dir, namespace=None, pins=None):
        self.specs = tuple(specs)
        self.pins = dict(pins or {})   # {absolute path: SHA-256} of the run's inputs
        self.domain_id = domain_id
        self.namespace = "/" + (namespace or "").strip("/")
        self.work_dir = Path(work_dir)
        self.log_dir = self.work_dir / "log"
        self.endpoints_dir = self.work_dir / "endpoints"
        self.procs = {}
        self.stopped_since = {}   # {name: monotonic time it was first seen stopped}

    def start(self):
        """Write each node's params file and start its process."""
        params_dir = self.work_dir / "params"
        params_dir.mkdir(parents=True, exist_ok=True)
        self.log_dir.mkdir(parents=True, exist_ok=True)
        self.endpoints_dir.mkdir(mode=0o700, exist_ok=True)
        for stale in self.endpoints_dir.glob("*.json"):   # a reused work folder
            stale.unlink()
        env = ros_env(self.domain_id, self.log_dir)
        env[ENDPOINTS_ENV] = str(self.endpoints_dir)
        commands = {}
        for spec in self.specs:
            params_file = params_dir / f"{spec.name}.yaml"
            params = {k: list(v) if isinstance(v, tuple) else v for k, v in spec.params.items()}
            text = yaml.safe_dump(
                {node_key(self.namespace, spec.name): {"ros__parameters": params}}).encode()
            params_file.write_bytes(text)
            self.pins[str(params_file.resolve())] = sha256_bytes(text)
            commands[spec.name] = [sys.executable, "-m", spec.module_name, "--ros-args",
                                   "-r", f"__node:={spec.name}",
                                   *namespace_args(self.namespace),
                                   "--params-file", str(params_file)]
        env[PINS_ENV] = str(write_pins(self.work_dir / "input_pins.json", self.pins))
        for spec in self.specs:
            cmd = commands[spec.name]
            with open(self.log_dir / f"{spec.name}.log", "wb") as log:
                self.procs[spec.name] = subprocess.Popen(
                    cmd, env=env, stdout=log, stderr=subprocess.STDOUT,
                    stdin=subprocess.DEVNULL, start_new_session=True)
        return self

    def exited(self):
        """{name: return code} of the processes that have ended."""
        return {n: p.returncode for n, p in self.procs.items() if p.poll() is not None}

    def check_alive(self, allowed=()):
        """Raise NodeDied naming the first node that ended (except those in ``allowed``), or
        that has been stopped (SIGSTOP) for STOPPED_LIMIT_S."""
        for name, code in self.exited().items():
            if name not in allowed:
                verb = "stopped before the run ended" if code == 0 else "died"
                raise NodeDied(f"node '{name}' {verb} ({describe_exit(code)}); its log: "
                               f"{self.log_dir / (name + '.log')}: {self.log_tail(name)}")
        self.check_stopped()

    def check_stopped(self, limit=STOPPED_LIMIT_S):
        """NodeDied naming a node whose process has been stopped (state T: SIGSTOP, or t: a
        debugger) for ``limit`` [s]; a node continued (SIGCONT) in time is forgotten."""
        now = time.monotonic()
        for name, proc in self.procs.items():
            if proc.poll() is None and process_state(proc.pid) in ("T", "t"):
                since = self.stopped_since.setdefault(name, now)
                if now - since >= limit:
                    raise NodeDied(f"node '{name}' (pid {proc.pid}) has been stopped for "
                                   f"{now - since:.0f} s (SIGSTOP or a debugger: process state "
                                   f"T); the run cannot go on without it")
            else:
                self.stopped_since.pop(name, None)

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
                    os.kill(proc.pid, signal.SIGCONT)   # a stopped node must see it too
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
