"""DDS on loopback and ROS_DOMAIN_ID honoured by real node processes (the half of
test_ros_network that starts ROS 2 nodes: a file of its own, test/conftest.py: ROS_FILES)."""
import json
import os
import signal
import subprocess
import sys
import time

import pytest
from test_campaign_graph import SHORT_PROTOCOL
from test_ros_network import (
    RANGE,
    _children,
    _environ,
    _is_node,
    _socket_table,
    is_loopback,
    process_sockets,
)

from motoflex_ros.launcher.domain import DomainLock
from motoflex_ros.nodes.dds import PROFILE_ENV, loopback_profile


def _node_env(domain_id, tmp_path, **extra):
    env = {k: v for k, v in os.environ.items()
           if k not in ("FASTRTPS_DEFAULT_PROFILES_FILE", "MOTOFLEX_DDS")}
    return {**env, "ROS_DOMAIN_ID": str(domain_id), "ROS_LOG_DIR": str(tmp_path / "log"),
            RANGE: "SUBNET", **extra}


def _node_sockets(tmp_path):
    """Start sim_clock on its own; its sockets once discovery runs, its exit code, stderr."""
    with DomainLock() as lock:
        proc = subprocess.Popen([sys.executable, "-m", "motoflex_ros.nodes.sim_clock",
                                 "--ros-args", "-p", "duration:=100.0",
                                 "-p", "stall_timeout:=3600.0"],
                                env=_node_env(lock.domain_id, tmp_path),
                                text=True, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
        try:
            # a hang guard, not a timing check: under a loaded machine the node's imports
            # alone took over 30 s once (full suite beside other jobs, load average 9)
            deadline, sockets = time.monotonic() + 180.0, []
            while len(sockets) < 3 and time.monotonic() < deadline and proc.poll() is None:
                time.sleep(0.2)
                sockets = process_sockets(proc.pid)
            time.sleep(1.0)   # discovery has started by now
            sockets = process_sockets(proc.pid) if proc.poll() is None else sockets
            early = proc.poll()
        finally:
            proc.send_signal(signal.SIGINT)
            _, err = proc.communicate(timeout=30)
    return sockets, early, err


def test_node_entry_point_binds_loopback_by_itself(tmp_path):
    """A node started on its own (``ros2 run``, no launcher) sets the profile too. Every
    socket it binds is on loopback. The node is still running when looked at: a sim_clock
    alone waits for a subscriber of /clock (it once counted its own time source's and ran its
    whole run to itself, ending at start-up in about one start in ten)."""
    pytest.importorskip("rclpy")
    sockets, early, err = _node_sockets(tmp_path)
    assert early is None, (early, err)
    assert all(is_loopback(address) for _, address, _ in sockets), sockets
    assert len(sockets) >= 3, (sockets, err)


def test_node_refuses_unknown_dds_mode(tmp_path):
    pytest.importorskip("rclpy")
    with DomainLock() as lock:
        run = subprocess.run([sys.executable, "-m", "motoflex_ros.nodes.sim_clock"],
                             env=_node_env(lock.domain_id, tmp_path, MOTOFLEX_DDS="wifi"),
                             capture_output=True, text=True, timeout=60)
    assert run.returncode == 2
    assert "sim_clock: error: MOTOFLEX_DDS='wifi'" in run.stderr and "Traceback" not in run.stderr


@pytest.mark.slow
def test_campaign_sockets_on_loopback_and_explicit_domain_honoured(tmp_path):
    """A whole campaign (swingarm, --json) on an explicit ROS_DOMAIN_ID: every socket of every
    process of the run is bound to loopback, every node runs on that domain, the id is
    printed on stderr at the start and stdout stays clean JSON. On the short protocol
    (test/data/short_bench.yaml): the sockets are the point, not the numbers."""
    pytest.importorskip("rclpy")
    with DomainLock() as free:
        domain = free.domain_id
    bag = tmp_path / "run"
    proc = subprocess.Popen([sys.executable, "-m", "motoflex_ros.cli.main", "campaign",
                             "--component", "swingarm", "--out", str(bag), "--report", "none",
                             "--json", "--protocol", SHORT_PROTOCOL],
                            env=_node_env(domain, tmp_path, TMPDIR=str(tmp_path)), text=True,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    seen, node_envs = {}, {}
    try:
        deadline = time.monotonic() + 300
        while proc.poll() is None and time.monotonic() < deadline:
            table = _socket_table()
            for pid in [proc.pid, *_children(proc.pid)]:
                try:
                    seen.setdefault(pid, set()).update(process_sockets(pid, table))
                    if pid != proc.pid and _is_node(pid):
                        node_envs[pid] = _environ(pid)   # a node's start env
                except OSError:
                    continue   # ended meanwhile
            time.sleep(0.5)
        out, err = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.communicate()
    assert proc.returncode == 0, err
    printed = json.loads(out)   # stdout: the results as JSON, nothing else
    assert "swingarm" in printed and printed["bag"] == str(bag)
    assert printed["stability"] is None       # no motorcycle without all three components
    assert f"motoflex: ROS_DOMAIN_ID {domain} (from ROS_DOMAIN_ID); DDS on loopback" in err
    assert len(node_envs) >= 5, node_envs
    assert {env.get("ROS_DOMAIN_ID") for env in node_envs.values()} == {str(domain)}
    assert {env.get(PROFILE_ENV) for env in node_envs.values()} == {str(loopback_profile())}
    with_sockets = {pid: s for pid, s in seen.items() if s}
    assert len(with_sockets) >= 6, seen   # the campaign's own node + 5 node processes
    assert sum(map(len, with_sockets.values())) >= 18, seen
    outside = {pid: [s for s in socks if not is_loopback(s[1])]
               for pid, socks in with_sockets.items()}
    assert not any(outside.values()), outside
    status = json.loads((bag / "status.json").read_text())
    assert status["status"] == "complete"
