"""Real node processes: parameter errors, recorder signals, repair after SIGKILL, domain isolation.

Each test holds its own ROS_DOMAIN_ID (DomainLock), logs to tmp, and ends the processes it
started by their own pid.
"""
import os
import signal
import subprocess
import sys
import time

import pytest

pytest.importorskip("rclpy")
from rosbags.highlevel import AnyReader  # noqa: E402

from motoflex_ros.launcher.domain import DomainLock  # noqa: E402
from motoflex_ros.launcher.graph import ros_env  # noqa: E402
from motoflex_ros.record import mcap_bag  # noqa: E402


@pytest.fixture
def env(tmp_path):
    with DomainLock() as lock:
        yield ros_env(lock.domain_id, tmp_path / "log")


def _node(name, env, *params, params_file=None, ros_args=(), **popen):
    cmd = [sys.executable, "-m", f"motoflex_ros.nodes.{name}", "--ros-args", *ros_args]
    for p in params:
        cmd += ["-p", p]
    if params_file:
        cmd += ["--params-file", str(params_file)]
    return subprocess.Popen(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True, **popen)


def _end(*procs):
    for proc in procs:
        if proc.poll() is None:
            os.kill(proc.pid, signal.SIGKILL)
        proc.communicate(timeout=10)


def _wait_for_file_size(path, size, proc, timeout=30.0):
    deadline = time.monotonic() + timeout
    while not (path.exists() and path.stat().st_size > size):
        assert proc.poll() is None, proc.communicate()
        assert time.monotonic() < deadline, f"{path} did not grow"
        time.sleep(0.1)


def _clock_times(bag):
    with AnyReader([bag]) as reader:
        return [m.clock.sec * 10**9 + m.clock.nanosec
                for conn, _, raw in reader.messages()
                for m in [reader.deserialize(raw, conn.msgtype)]]


@pytest.mark.parametrize("content, expected", [
    ("sim_clock:\n  ros__parameters:\n    window: 0\n",
     "parameter 'window' = 0 is not allowed (expected int in [1, 1e+06])"),
    # a section named for the node refuses unknown keys, even beside a wildcard section
    ("/**:\n  ros__parameters:\n    seed: 3\n"
     "sim_clock:\n  ros__parameters:\n    dt: 1.0e-3\n    windw: 5\n",
     "unknown parameter 'windw' (known: ack_from, dt, duration, stall_timeout, wait_for, "
     "window)"),
    ("sim_clock:\n  ros__parameters:\n    dt: 'fast'\n",
     "parameter 'dt' = 'fast' has the wrong type (expected float in [1e-06, 1])\n"),
])
def test_nodes_params_file_bad_value_clear_error(tmp_path, env, content, expected):
    params = tmp_path / "params.yaml"
    params.write_text(content)
    proc = _node("sim_clock", env, params_file=params)
    out, err = proc.communicate(timeout=60)
    assert proc.returncode == 2, (out, err)
    assert expected in err
    assert "Traceback" not in err


def test_nodes_wildcard_section_for_other_nodes_ignored(tmp_path, env):
    """A '/**:' section may hold parameters of other nodes (issue 16, point 6): the node
    says so at debug level, takes its own (stall_timeout) and runs: alone, to its wait for a
    subscriber of /clock, which it gives up after stall_timeout.
    """
    params = tmp_path / "params.yaml"
    params.write_text("/**:\n  ros__parameters:\n    seed: 3\n    dt: 2.0e-3\n"
                      "    stall_timeout: 0.5\n")
    proc = _node("sim_clock", env, params_file=params,
                 ros_args=["--log-level", "sim_clock:=debug"])
    out, err = proc.communicate(timeout=60)
    assert proc.returncode == 2, (out, err)
    assert "gave up after 0.5 s waiting for a subscriber of /clock" in err
    assert "unknown parameter" not in err
    assert "ignoring parameter 'seed' of a wildcard params file section" in err


def test_nodes_waiting_node_says_why_and_honours_stall_timeout(env):
    """load_actuator alone (issue 16, point 6): it says what it waits for at once and every
    WAIT_LOG_PERIOD_S, and gives up after stall_timeout."""
    from motoflex_ros.nodes.pacing import WAIT_LOG_PERIOD_S
    stall_s = WAIT_LOG_PERIOD_S + 1.0
    start = time.monotonic()
    proc = _node("load_actuator", env, f"stall_timeout:={stall_s}")
    out, err = proc.communicate(timeout=60)
    waiting = "waiting for identification to announce on /rig/ready"
    assert proc.returncode == 2, (out, err)
    assert err.count(f"]: {waiting}") == 2, err
    assert f"gave up after {stall_s:g} s {waiting}" in err
    assert time.monotonic() - start < stall_s + 30


def test_nodes_params_file_missing_nonzero(tmp_path, env):
    proc = _node("sim_clock", env, params_file=tmp_path / "nope.yaml")
    _, err = proc.communicate(timeout=60)
    assert proc.returncode != 0
    assert "nope.yaml" in err


def test_recorder_existing_bag_clear_error(tmp_path, env):
    (tmp_path / "bag").mkdir()
    (tmp_path / "bag" / "other.txt").write_text("keep me")
    proc = _node("recorder", env, f"bag:={tmp_path / 'bag'}")
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 2 and "exists and is not an empty directory" in err
    assert sorted(p.name for p in (tmp_path / "bag").iterdir()) == ["other.txt"]


def _recorder_with_clock(env, bag):
    """A recorder of /clock (small chunks) and a lock-step sim_clock waiting for its acks."""
    recorder = _node("recorder", env, f"bag:={bag}", "topics:=['/clock']", "ack:=true",
                     "chunk_size:=4096")
    clock = _node("sim_clock", env, "dt:=0.001", "duration:=1000.0", "window:=20",
                  "ack_from:=['recorder']", "stall_timeout:=60.0")
    return recorder, clock


@pytest.mark.parametrize("signum", [signal.SIGINT, signal.SIGTERM])
def test_recorder_finishes_bag_on_signal_roundtrip(tmp_path, env, signum):
    bag = tmp_path / "bag"
    recorder, clock = _recorder_with_clock(env, bag)
    try:
        _wait_for_file_size(bag / "bag_0.mcap", 20000, recorder)
        os.kill(recorder.pid, signum)
        out, err = recorder.communicate(timeout=30)
        assert recorder.returncode == 0, err
    finally:
        _end(recorder, clock)
    info = mcap_bag.bag_info(bag)
    times = _clock_times(bag)
    assert info.count("/clock") == len(times) > 100
    assert times == [1_000_000 * k for k in range(len(times))]  # lock-step: no gap, in order
    assert f"({signal.Signals(signum).name})" in err


def test_recorder_sigkill_then_bag_repair_roundtrip(tmp_path, env):
    bag = tmp_path / "bag"
    recorder, clock = _recorder_with_clock(env, bag)
    try:
        _wait_for_file_size(bag / "bag_0.mcap", 30000, recorder)
        os.kill(recorder.pid, signal.SIGKILL)
        recorder.communicate(timeout=30)
    finally:
        _end(recorder, clock)
    with pytest.raises(mcap_bag.BagError, match="motoflex bag repair"):
        mcap_bag.bag_info(bag)
    cli = subprocess.run([sys.executable, "-m", "motoflex_ros.cli.main", "bag", "repair",
                          str(bag), "--json"], capture_output=True, text=True, timeout=60)
    assert cli.returncode == 0, cli.stderr
    times = _clock_times(bag)
    assert len(times) > 100 and times == [1_000_000 * k for k in range(len(times))]
    assert mcap_bag.bag_info(bag).count("/clock") == len(times)


def test_bag_cli_not_a_bag_clear_error(tmp_path):
    (tmp_path / "file.txt").write_text("x")
    for argv in (["bag", "info", str(tmp_path / "file.txt")], ["bag", "repair", str(tmp_path)],
                 ["replay", str(tmp_path / "missing")]):
        cli = subprocess.run([sys.executable, "-m", "motoflex_ros.cli.main", *argv],
                             capture_output=True, text=True, timeout=60)
        assert cli.returncode == 2, argv
        assert "not a bag" in cli.stderr and "Traceback" not in cli.stderr
    assert [p.name for p in tmp_path.iterdir()] == ["file.txt"]


def test_ros_domains_isolated(tmp_path):
    """Two graphs at once on two domain ids: each bag holds only its own clock."""
    runs = []
    with DomainLock() as a, DomainLock() as b:
        assert a.domain_id != b.domain_id
        for lock, duration in ((a, 0.5), (b, 0.8)):
            env = ros_env(lock.domain_id, tmp_path / f"log{lock.domain_id}")
            bag = tmp_path / f"bag{lock.domain_id}"
            recorder = _node("recorder", env, f"bag:={bag}", "ack:=true")  # records all topics
            clock = _node("sim_clock", env, "dt:=0.001", f"duration:={duration}",
                          "window:=20", "ack_from:=['recorder']")
            runs.append((bag, duration, recorder, clock))
        try:
            for _bag, _duration, recorder, clock in runs:
                assert clock.wait(timeout=120) == 0, clock.communicate()
                os.kill(recorder.pid, signal.SIGINT)
                assert recorder.wait(timeout=30) == 0
        finally:
            for run in runs:
                _end(*run[2:])
    for bag, duration, *_ in runs:
        info = mcap_bag.bag_info(bag)
        assert [t.name for t in info.topics] == ["/clock"]
        steps = round(duration / 0.001) + 1
        assert _clock_times(bag) == [1_000_000 * k for k in range(steps)]


def test_bad_protocol_file_clear_error(tmp_path, env):
    """A protocol file that does not exist: the node and the campaign name it; nothing written."""
    proc = _node("load_actuator", env, f"protocol:={tmp_path / 'nope.yaml'}")
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 2 and "nope.yaml: file not found" in err
    cli = subprocess.run([sys.executable, "-m", "motoflex_ros.cli.main", "campaign",
                          "--component", "swingarm", "--protocol", str(tmp_path / "nope.yaml"),
                          "--out", str(tmp_path / "run")], capture_output=True, text=True,
                         timeout=120, env=env)
    assert cli.returncode == 2 and "nope.yaml: file not found" in cli.stderr
    assert "Traceback" not in cli.stderr + err
    assert not (tmp_path / "run").exists()


def test_nodes_sequence_gap_reported_per_publisher(tmp_path, env):
    """Publisher A numbers 1, 2, 5, 6 (two lost), publisher B 1, 2, 3 interleaved on the same
    topic (none lost): counted per publisher, two gaps; per subscription B's numbers would have
    hidden A's gap and faked others."""
    import rclpy
    from rclpy.node import Node
    from std_msgs.msg import String

    from motoflex_ros.nodes.endpoints import InputGuard
    context = rclpy.Context()
    rclpy.init(args=[], context=context, domain_id=int(env["ROS_DOMAIN_ID"]))
    try:
        node = Node("gap_probe", context=context)
        sub = node.create_subscription(String, "/probe", lambda m: None, 10)
        guard = InputGuard(node, None)
        a, b = b"A" * 16, b"B" * 16
        for gid, seq in ((a, 1), (b, 1), (a, 2), (b, 2), (a, 5), (b, 3), (a, 6)):
            guard.check(sub, gid, seq)
        assert guard.gaps == 2
        node.destroy_node()
    finally:
        rclpy.shutdown(context=context)
