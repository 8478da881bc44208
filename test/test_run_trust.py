"""Trust every run (issue 23, run-level points): a run pinned to its inputs (2), nodes that refuse
what they do not understand (11), reports only of what the run recorded (8).

Point 2 is tested three ways: the pin check itself (a changed file fails the read naming it), a
node started with pins its file no longer matches (stops at start-up, naming the file), and a
whole campaign whose component file is edited while it runs (fails naming the file, status
"failed", no identification.json, no process left). The provenance and identification.json
hashes of a complete run are asserted in test_campaign_graph.py (no extra graph run).
"""
import json
import os
import subprocess
import sys
import time
from pathlib import Path

import pytest
from processes import processes_naming
from test_campaign_graph import SHORT_PROTOCOL, _wait_for_recording

pytest.importorskip("rclpy")
from motoflex_ros import input_pins  # noqa: E402
from motoflex_ros.config import config_path  # noqa: E402
from motoflex_ros.launcher.status import read_status  # noqa: E402

FAULT_S = 10.0


def _one_line_error(text):
    """The last line of stderr: one line, no traceback."""
    assert "Traceback" not in text, text
    lines = text.strip().splitlines()
    assert lines, "no message"
    return lines[-1]


# ---------------------------------------------------------------- point 2: inputs pinned
def test_read_input_is_checked_against_the_runs_pins(tmp_path, monkeypatch):
    config = tmp_path / "c.yaml"
    config.write_text("a: 1\n")
    with input_pins.recording_inputs() as seen:
        assert input_pins.read_input(config) == b"a: 1\n"
    assert seen == {str(config.resolve()): input_pins.sha256_bytes(b"a: 1\n")}
    pins_file = input_pins.write_pins(tmp_path / "pins.json", seen)
    monkeypatch.setenv(input_pins.PINS_ENV, str(pins_file))
    input_pins.read_input(config)   # unchanged: fine
    config.write_text("a: 2\n")
    with pytest.raises(input_pins.InputChanged, match=r"c\.yaml: input changed during the run"):
        input_pins.read_input(config)
    with pytest.raises(input_pins.InputChanged, match=r"c\.yaml: input changed"):
        input_pins.check_pins(seen)
    config.unlink()
    with pytest.raises(input_pins.InputChanged, match=r"c\.yaml: input of the run is gone"):
        input_pins.check_pins(seen)


def _node(module, *args, env=None, timeout=60):
    return subprocess.run([sys.executable, "-m", f"motoflex_ros.nodes.{module}", *args],
                          capture_output=True, text=True, timeout=timeout,
                          env={**os.environ, **(env or {})})


def test_node_refuses_a_component_file_that_is_not_the_pinned_one(tmp_path):
    """A node that reads an input the launcher pinned with other bytes stops at once, naming
    the file (the second half of issue 23's point 2 defect: nodes started after an edit)."""
    component = tmp_path / "swingarm_copy.yaml"
    component.write_bytes(config_path("components", "swingarm").read_bytes())
    pins = input_pins.write_pins(tmp_path / "pins.json",
                                 {str(component.resolve()): input_pins.sha256_bytes(b"old")})
    start = time.monotonic()
    done = _node("component_simulator", "--ros-args", "-p", f"components:=['{component}']",
                 env={input_pins.PINS_ENV: str(pins), "ROS_LOG_DIR": str(tmp_path / "log")})
    assert time.monotonic() - start < 60.0
    assert done.returncode == 2
    line = _one_line_error(done.stderr)
    assert str(component) in line and "input changed during the run" in line


def _campaign(tmp_path, *args, **extra_env):
    env = dict(os.environ, TMPDIR=str(tmp_path), OPENBLAS_NUM_THREADS="1", **extra_env)
    return subprocess.Popen([sys.executable, "-m", "motoflex_ros.cli.main", "campaign", *args],
                            env=env, text=True, stdout=subprocess.PIPE, stderr=subprocess.PIPE)


def test_component_file_edited_mid_run_fails_the_campaign_naming_it(tmp_path):
    """Issue 23, point 2: the component's YAML is edited while the campaign runs. The run
    fails naming the file (its nodes read it before the edit; the launcher's end check sees
    the change), status.json 'failed', no identification.json, no node left. On the short
    protocol (test/data/short_bench.yaml): the launcher checks the pins after every node
    stopped, so the edit, made as the bag passes 20 kB, still comes in the run."""
    component = tmp_path / "swingarm_copy.yaml"
    original = config_path("components", "swingarm").read_text()
    component.write_text(original)
    bag = tmp_path / "run"
    proc = _campaign(tmp_path, "--component", str(component), "--out", str(bag),
                     "--report", "none", "--protocol", SHORT_PROTOCOL)
    try:
        _wait_for_recording(proc, bag)
    except BaseException:
        proc.kill()   # never leave the campaign behind a failed wait
        proc.communicate()
        raise
    # a stiffer arm: another model, as in the report (a changed material)
    component.write_text(original.replace("E: 7.0e10", "E: 9.0e10"))
    _, err = proc.communicate(timeout=300)
    assert proc.returncode != 0
    line = _one_line_error(err)
    assert str(component.resolve()) in line and "input changed during the run" in line, line
    status = read_status(bag)
    assert status["status"] == "failed" and str(component.resolve()) in status["reason"]
    assert not (bag / "identification.json").exists()
    assert processes_naming(str(tmp_path), also="motoflex_ros.nodes") == []


# ---------------------------------------------------------------- point 11: unknown arguments
@pytest.mark.parametrize("node", ["identification", "recorder"])
@pytest.mark.parametrize("args", [("--params-file", "p.yaml"), ("--bogus-flag", "x")])
def test_nodes_refuse_unknown_command_line_arguments(tmp_path, node, args):
    """``identification --params-file p.yaml`` (no --ros-args) and ``--bogus-flag x`` ran
    with the defaults; now: one line naming the argument, exit 2, at once."""
    (tmp_path / "p.yaml").write_text("identification: {ros__parameters: {seed: 3}}\n")
    start = time.monotonic()
    done = subprocess.run([sys.executable, "-m", f"motoflex_ros.nodes.{node}", *args],
                          capture_output=True, text=True, timeout=60, cwd=tmp_path,
                          env=dict(os.environ, ROS_LOG_DIR=str(tmp_path / "log")))
    assert time.monotonic() - start < FAULT_S
    assert done.returncode == 2
    line = _one_line_error(done.stderr)
    assert line.startswith(f"{node}: error: unknown argument '{args[0]}'"), line


def test_provenance_and_identification_name_the_inputs_hashes(tmp_path):
    """The campaign's pinned inputs: the shipped component and protocol files by SHA-256,
    and the vehicle file whose carried inertia is the principal hinges' metric, read once; the
    identification node's record of what it read is the same (no graph run: the pinning of
    campaign_inputs and the node's own setup are compared directly)."""
    from motoflex_ros.launcher.campaign_graph import VEHICLE, campaign_inputs
    from motoflex_ros.nodes.bench_graph import campaign_setups
    _, pinned = campaign_inputs(["swingarm"])
    component = config_path("components", "swingarm")
    protocol = Path(str(component).replace("components", "protocols"))
    assert pinned == {str(p.resolve()): input_pins.sha256_bytes(p.read_bytes())
                      for p in (component, protocol, config_path("vehicles", VEHICLE))}
    read = {}
    campaign_setups({"components": ["swingarm"], "noise": -1.0, "protocol": ""}, read)
    assert read == {"swingarm": pinned}
    # with all three components (the vehicle simulator runs) the vehicle's file is pinned too
    _, everything = campaign_inputs(["frame", "front_assembly", "swingarm"])
    assert str(config_path("vehicles", VEHICLE).resolve()) in everything
    assert json.loads(json.dumps(everything)) == everything


# ---------------------------------------------------------------- point 3: a bounded live store
def test_live_measured_inputs_keep_a_rolling_bound(tmp_path):
    """Issue 23, point 3: with ``max_frames`` 50, 120 loads and marker frames and one PoseArray
    of 100,000 poses: the 50 most recent of each are kept, 70 counted as dropped oldest, the
    huge one dropped unread by its size and counted; memory is the bound's, not the stream's.
    (A real node and publisher in one process; benchmarks/bench_live_memory.py measures a
    30-minute stream at 1 kHz.)"""
    import rclpy
    from geometry_msgs.msg import Pose, PoseArray, WrenchStamped
    from rclpy.executors import SingleThreadedExecutor
    from rclpy.qos import HistoryPolicy, QoSProfile, ReliabilityPolicy
    from test_measured_live import bench_yaml

    from motoflex_ros.launcher.domain import DomainLock
    from motoflex_ros.nodes.measured_inputs import MeasuredInputs

    bench = tmp_path / "bench.yaml"
    bench.write_text(bench_yaml("rig", (0.5, 0.0, 0.0)))
    params = {"bench_file": str(bench), "load_topic": "", "markers_topic": "",
              "marker_msg": "PoseArray", "n_markers": 0, "identify_topic": "",
              "idle_timeout_s": 0.0, "qos": "reliable", "max_frames": 50}
    with DomainLock() as lock:
        context = rclpy.Context()
        rclpy.init(context=context, domain_id=lock.domain_id)
        try:
            node = rclpy.create_node("identification", context=context)
            live = MeasuredInputs(node, params)
            rig = rclpy.create_node("rig", context=context)
            qos = QoSProfile(depth=1, history=HistoryPolicy.KEEP_ALL,
                             reliability=ReliabilityPolicy.RELIABLE)
            loads = rig.create_publisher(WrenchStamped, "/bench/rig/load", qos)
            markers = rig.create_publisher(PoseArray, "/bench/rig/markers/measured", qos)
            executor = SingleThreadedExecutor(context=context)
            executor.add_node(node)
            executor.add_node(rig)
            while not live.inputs_ready() or loads.get_subscription_count() < 1 or \
                    markers.get_subscription_count() < 1:
                executor.spin_once(timeout_sec=0.1)
            huge = PoseArray(poses=[Pose() for _ in range(100_000)])
            for k in range(120):
                wrench, frame = WrenchStamped(), PoseArray(poses=[Pose() for _ in range(4)])
                for msg in (wrench, frame):
                    msg.header.stamp.sec, msg.header.stamp.nanosec = 1, 1_000_000 * k
                loads.publish(wrench)
                markers.publish(frame)
                if k == 60:
                    markers.publish(huge)
                executor.spin_once(timeout_sec=0)
            while live.received.get("load", 0) < 120 or live.received.get("markers", 0) < 120:
                executor.spin_once(timeout_sec=0.1)
            executor.spin_once(timeout_sec=0.2)
        finally:
            rclpy.try_shutdown(context=context)
    assert live.received["oversized"] == 1
    assert live.received["dropped_oldest_load"] == live.received["dropped_oldest_markers"] == 70
    stamps, _, _ = live.loads.rows()
    assert stamps.tolist() == [10**9 + 1_000_000 * k for k in range(70, 120)]
    kept = live.frames.messages()
    assert [s for s, _ in kept] == stamps.tolist() and all(len(p) == 4 for _, p in kept)
    assert live.frames.nbytes() <= 50 * 4 * (8 + 24 + 8)   # the bound's arrays, no more


# ---------------------------------------------------------------- point 9: a full domain
PAIR = """import os, sys, time
from motoflex_ros.nodes.dds import configure_dds
configure_dds(os.environ)
import rclpy
from rclpy.executors import SingleThreadedExecutor
from std_msgs.msg import String
got, nodes, executors = [], [], []
for name in ("talker", "listener"):
    context = rclpy.Context()
    rclpy.init(context=context, domain_id=int(sys.argv[1]))
    nodes.append(rclpy.create_node(name, context=context))
    executors.append(SingleThreadedExecutor(context=context))
    executors[-1].add_node(nodes[-1])
publisher = nodes[0].create_publisher(String, "chat", 10)
nodes[1].create_subscription(String, "chat", got.append, 10)
deadline = time.monotonic() + float(sys.argv[2])
while not got and time.monotonic() < deadline:
    publisher.publish(String(data="hello"))
    for executor in executors:
        executor.spin_once(timeout_sec=0.05)
print("received" if got else "nothing")
"""


def _occupy_participant_ids(domain, count):
    """Bind the unicast ports of participant ids 0..count-1 of ``domain`` on 127.0.0.1, as
    ``count`` DDS participants of this host do: Fast DDS gives a new participant the first id
    whose ports are free, so the run's participants come after them (what 100 real
    participants in one process do too, checked by hand: 24 s to start them, the pair then
    discovered in 1.5 s; this costs nothing). Returns the sockets."""
    import socket

    from motoflex_ros.launcher.domain import DOMAIN_GAIN, PORT_BASE
    sockets = []
    for pid in range(count):
        for port in (10 + 2 * pid, 11 + 2 * pid):   # metatraffic and user unicast
            s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
            s.bind(("127.0.0.1", PORT_BASE + DOMAIN_GAIN * domain + port))
            sockets.append(s)
    return sockets


def test_a_hundred_participants_in_the_domain_leave_room_for_a_run(tmp_path):
    """Issue 23, point 9: the loopback profile announced to the first 32 participant ids of
    a domain; a run whose participants came after 34 others never discovered itself (with 32
    this test's pair exchanges nothing in 15 s). With 100 participants in the domain two
    more must find each other."""
    from motoflex_ros.launcher.domain import DomainLock
    with DomainLock() as lock:
        sockets = _occupy_participant_ids(lock.domain_id, 100)
        try:
            pair = subprocess.run([sys.executable, "-c", PAIR, str(lock.domain_id), "30"],
                                  env=dict(os.environ, ROS_LOG_DIR=str(tmp_path / "log")),
                                  capture_output=True, text=True, timeout=120)
        finally:
            for s in sockets:
                s.close()
    assert pair.stdout.strip() == "received", pair


def test_campaign_in_a_domain_beyond_the_profiles_reach_is_refused_naming_it(tmp_path):
    """When the domain already holds more participants than the loopback profile's
    maxInitialPeersRange leaves room for, the campaign stops at once saying so (it used to
    wait 40 s and blame a node that did not announce itself)."""
    from motoflex_ros.launcher.domain import DomainLock
    from motoflex_ros.nodes.dds import loopback_profile
    with DomainLock() as lock:
        domain = lock.domain_id
    sockets = _occupy_participant_ids(domain, 118)
    try:
        start = time.monotonic()
        proc = _campaign(tmp_path, "--component", "swingarm", "--out", str(tmp_path / "run"),
                         "--report", "none", ROS_DOMAIN_ID=str(domain))
        _, err = proc.communicate(timeout=120)
    finally:
        for s in sockets:
            s.close()
    assert proc.returncode == 2 and time.monotonic() - start < FAULT_S
    line = _one_line_error(err)
    assert f"ROS_DOMAIN_ID {domain} has 118 DDS participants" in line, line
    assert "maxInitialPeersRange" in line and str(loopback_profile()) in line
    assert not (tmp_path / "run").exists()   # refused before any node started


# ---------------------------------------------------------------- hostile run cases of our own
def test_node_refuses_a_params_file_changed_after_the_launcher_pinned_it(tmp_path):
    """The launcher pins each node's params file too: one rewritten between the launcher
    writing it and the node reading it (another process, a full disk's truncation) stops
    the node at start-up naming the file, before rclpy uses it."""
    params = tmp_path / "identification.yaml"
    params.write_text("identification: {ros__parameters: {seed: 1}}\n")
    pins = input_pins.write_pins(tmp_path / "pins.json", {
        str(params.resolve()): input_pins.sha256_bytes(b"identification: {}\n")})
    done = _node("identification", "--ros-args", "--params-file", str(params),
                 env={input_pins.PINS_ENV: str(pins), "ROS_LOG_DIR": str(tmp_path / "log")})
    assert done.returncode == 2
    line = _one_line_error(done.stderr)
    assert str(params) in line and "input changed during the run" in line, line


@pytest.mark.parametrize("pins_text", [None, "not json", "[1, 2]"])
def test_node_refuses_unreadable_pins(tmp_path, pins_text):
    """MOTOFLEX_INPUT_PINS naming a missing file, or one that is not a mapping: the node
    cannot hold its inputs to anything; one line naming the file, exit 2."""
    pins = tmp_path / "pins.json"
    if pins_text is not None:
        pins.write_text(pins_text)
    done = _node("component_simulator", "--ros-args", "-p", "components:=['swingarm']",
                 env={input_pins.PINS_ENV: str(pins), "ROS_LOG_DIR": str(tmp_path / "log")})
    assert done.returncode == 2
    line = _one_line_error(done.stderr)
    assert str(pins) in line and "input pins" in line, line


def test_campaign_into_a_folder_in_use_is_refused_at_once(tmp_path):
    """Two runs, one folder: the second campaign into a folder that holds a run (here a
    finished one's files) stops at once naming it, and leaves the folder as it was."""
    folder = tmp_path / "run"
    folder.mkdir()
    (folder / "status.json").write_text('{"status": "complete"}\n')
    before = sorted(p.name for p in folder.iterdir())
    start = time.monotonic()
    proc = _campaign(tmp_path, "--component", "swingarm", "--out", str(folder), "--report",
                     "none")
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 2 and time.monotonic() - start < FAULT_S
    line = _one_line_error(err)
    assert str(folder) in line and "not an empty directory" in line, line
    assert sorted(p.name for p in folder.iterdir()) == before
    assert (folder / "status.json").read_text() == '{"status": "complete"}\n'
