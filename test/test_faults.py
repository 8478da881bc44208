"""Fault injection (issue 13): each fault ends the run at once, named, and leaves nothing that
looks like a success.

Faults: a foreign publisher on a bench topic, on /clock and on /identification/results; NaN,
Inf, out-of-range and backwards-stamped bench messages; SIGINT or SIGTERM of each node (both
of the load actuator; SIGNAL_PAIRS says why) and SIGTERM of the campaign (SIGKILL of each
node, SIGINT and SIGKILL of the campaign are the ``faults``-marked tests of
test_campaign_graph.py); two runs in one ROS domain. Each case
checks: a non-zero exit within FAULT_S of the fault, a message naming what happened (no
traceback), no process left, a bag that reads as it is (the recorder finished it), status.json
"failed" with the reason, and no identification.json. The campaigns are the shortest (swingarm,
--report none); the message faults replay a few hundred samples of bags/example, doctored, into
a fresh identification node.

Run on their own with ``./test.sh -m faults``.
"""
import json
import math
import os
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest

pytest.importorskip("rclpy")
from test_campaign_graph import (  # noqa: E402  (the campaign tests' helpers)
    COMPONENT,
    _campaign,
    _our_processes,
    _wait_for_recording,
    interruptible,
)

from motoflex_ros.launcher.status import read_status  # noqa: E402
from motoflex_ros.record import mcap_bag  # noqa: E402

FAULT_S = 10.0   # longest time from a fault to the run's non-zero exit [s]
EXAMPLE = Path(__file__).resolve().parents[1] / "bags" / "example"
NODES = ("load_actuator", "component_simulator", "displacement_sensor", "identification",
         "recorder")


def _cmdline(pid):
    try:
        return Path(f"/proc/{pid}/cmdline").read_bytes().replace(b"\0", b" ").decode()
    except OSError:
        return ""


def node_pid(marker, name):
    """Pid of node ``name`` among the node processes of ``marker`` (a test's tmp dir)."""
    return next(p for p in _our_processes(str(marker))
                if f"motoflex_ros.nodes.{name} " in _cmdline(p))


def domain_of(pid):
    """ROS_DOMAIN_ID in the environment of process ``pid``."""
    environ = Path(f"/proc/{pid}/environ").read_bytes().split(b"\0")
    return int(next(v for v in environ if v.startswith(b"ROS_DOMAIN_ID=")).split(b"=")[1])


def wait_gone(marker, timeout):
    """Wait until no node process of ``marker`` is left; returns those still there, after
    killing them (by their own pid) so that a failed test leaves nothing behind."""
    deadline = time.monotonic() + timeout
    while _our_processes(marker) and time.monotonic() < deadline:
        time.sleep(0.1)
    left = _our_processes(marker)
    for pid in left:
        try:
            os.kill(pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
    return left


class Run:
    """A swingarm campaign in ``tmp_path``: started, then a fault, then its end checked."""

    def __init__(self, tmp_path, forced_domain=None):
        self.tmp_path = tmp_path
        self.bag = tmp_path / "run"
        args = ("--out", str(self.bag), "--report", "none")
        if forced_domain is None:
            self.proc = _campaign(tmp_path, *args)
        else:   # the second of two campaigns in one domain
            self.proc = subprocess.Popen(
                [sys.executable, "-c", FORCED_DOMAIN, str(forced_domain), "campaign",
                 "--component", COMPONENT, *args], text=True, stdout=subprocess.PIPE,
                stderr=subprocess.PIPE, env=dict(os.environ, TMPDIR=str(tmp_path)),
                preexec_fn=interruptible)
        self.fault_at = None
        self._ended = None   # (exit code, stderr, monotonic time of the exit)
        self._waiter = threading.Thread(target=self._wait, daemon=True)
        self._waiter.start()   # reads the pipes as they fill; notes when the campaign ended

    def _wait(self):
        try:
            _, err = self.proc.communicate(timeout=300)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            _, err = self.proc.communicate()
        self._ended = (self.proc.returncode, err, time.monotonic())

    def running(self):
        """Wait until the campaign records; returns self."""
        _wait_for_recording(self.proc, self.bag)
        return self

    @classmethod
    def together(cls, tmp_path, count):
        """``count`` campaigns started at once (in tmp_path/0, 1...), each recording."""
        runs = []
        for i in range(count):
            (tmp_path / str(i)).mkdir()
            runs.append(cls(tmp_path / str(i)))
        return [run.running() for run in runs]

    def domain_id(self):
        return domain_of(node_pid(self.tmp_path, "recorder"))

    def fault(self):
        """Note the moment of the fault (which must find the campaign running)."""
        self.fault_at = time.monotonic()
        assert self._ended is None, ("the campaign ended before the fault", self._ended)

    def end(self):
        """(exit code, stderr, seconds from the fault to the exit, or None without a fault)."""
        self._waiter.join()
        code, err, ended_at = self._ended
        return code, err, None if self.fault_at is None else ended_at - self.fault_at

    def assert_failed_cleanly(self, expected, bag_started=True):
        """The checks every fault shares; ``expected``: text the message must contain."""
        code, err, seconds = self.end()
        left = wait_gone(str(self.tmp_path), 5.0)
        assert code != 0, err
        assert seconds < FAULT_S, (seconds, err)
        assert expected in err, err
        assert "Traceback" not in err, err
        assert left == []
        assert_bag_readable(self.bag, bag_started)
        assert not (self.bag / "identification.json").exists()
        status = read_status(self.bag)
        if bag_started or status is not None:
            assert status["status"] == "failed" and expected in status["reason"], status
        return err


def assert_bag_readable(bag, started=True):
    """The bag reads as it is: every fault here leaves the recorder time to finish it (a run
    that failed before it started may have none, or an empty one)."""
    if not started and not list(bag.glob("*.mcap")):
        return      # no bag yet (a failed campaign's folder may hold only its kept node logs)
    info = mcap_bag.bag_info(bag)
    assert info.count(f"/bench/{COMPONENT}/load") > 0 or not started


# --- signals -------------------------------------------------------------------------------

def _expected_for_node(victim, signum):
    name = signal.Signals(signum).name
    if victim == "load_actuator":   # the pacer: its end must not pass for the run's end
        return f"node 'load_actuator' failed (exit {128 + signum}: stopped by {name})"
    return f"stopped by {name}"


# SIGINT and SIGTERM take one code path in every node (nodes/node_main.py: one handler for
# both notes the signal's name and ends the loop; no node installs a handler of its own), so
# they differ only where the name is used: in the exit code 128 + signum of a node that ends
# itself (ENDS_ITSELF: the load actuator here), and in the words of the log. The load actuator
# gets both; every other node one of them (the two alternate), SIGKILL of each node being
# test_campaign_graph.py's test_campaign_fault_named_and_clean. Two campaigns at once.
SIGNAL_PAIRS = {
    "load_actuator": (("load_actuator", signal.SIGINT), ("load_actuator", signal.SIGTERM)),
    "simulator-and-sensor": (("component_simulator", signal.SIGTERM),
                             ("displacement_sensor", signal.SIGINT)),
    "identification-and-recorder": (("identification", signal.SIGTERM),
                                    ("recorder", signal.SIGINT)),
}


def test_signal_pairs_cover_every_node_and_both_signals():
    """Every node gets a clean signal in some campaign; the load actuator both of them."""
    cases = [case for pair in SIGNAL_PAIRS.values() for case in pair]
    assert {victim for victim, _ in cases} == set(NODES)
    assert {s for v, s in cases if v == "load_actuator"} == {signal.SIGINT, signal.SIGTERM}
    assert {s for _, s in cases} == {signal.SIGINT, signal.SIGTERM}


@pytest.mark.parametrize("pair", SIGNAL_PAIRS.values(), ids=SIGNAL_PAIRS.keys())
def test_sigint_and_sigterm_to_node_fail_run(tmp_path, pair):
    """Two campaigns at once, each with one node stopped by SIGINT or SIGTERM (see
    SIGNAL_PAIRS for why not both signals to every node)."""
    runs = Run.together(tmp_path, len(pair))
    for run, (victim, signum) in zip(runs, pair):
        run.fault()
        os.kill(node_pid(run.tmp_path, victim), signum)
    for run, (victim, signum) in zip(runs, pair):
        err = run.assert_failed_cleanly(_expected_for_node(victim, signum))
        assert f"node '{victim}'" in err


def test_sigstop_names_the_stalled_node_and_a_short_stop_is_survived(tmp_path):
    """Issue 23, point 10: SIGSTOP of the component simulator for 20 s (it used to fail the
    run after 30 s naming another node, the identification whose acknowledgement stalled):
    the run fails naming the stopped node (graph.STOPPED_LIMIT_S after the stop), the
    recorder still finishes the bag, nothing is left. Beside it, a second campaign whose
    identification node is stopped for 2 s and continued (SIGCONT) ends complete."""
    from motoflex_ros.launcher.graph import STOPPED_LIMIT_S
    stalled, paused = Run.together(tmp_path, 2)
    stalled.fault()
    victim = node_pid(stalled.tmp_path, "component_simulator")
    held = node_pid(paused.tmp_path, "identification")
    os.kill(victim, signal.SIGSTOP)
    os.kill(held, signal.SIGSTOP)
    time.sleep(2.0)
    os.kill(held, signal.SIGCONT)
    try:
        stalled.fault_at += STOPPED_LIMIT_S   # the run may wait that long for the node
        err = stalled.assert_failed_cleanly(f"node 'component_simulator' (pid {victim}) has "
                                            f"been stopped")
        assert "process state T" in err
    finally:
        try:
            os.kill(victim, signal.SIGCONT)   # (it was ended by the run; never leave it)
        except ProcessLookupError:
            pass
    code, err, _ = paused.end()
    assert code == 0, err
    assert read_status(paused.bag)["status"] == "complete"
    assert wait_gone(str(tmp_path), 5.0) == []


# --- foreign publishers --------------------------------------------------------------------

INTRUDER = """import os, sys, time
import rclpy
from rclpy.node import Node
sys.path.insert(0, sys.argv[3])
from test_faults import _forged
from motoflex_ros.nodes.dds import configure_dds
configure_dds(os.environ)   # the rig's own DDS set-up: discovery as between the run's nodes
rclpy.init(args=[], domain_id=int(sys.argv[1]))
node = Node("intruder")
topic = sys.argv[2]
msg, qos = _forged(topic)
publisher = node.create_publisher(type(msg), topic, qos)
print("advertised", flush=True)
while publisher.get_subscription_count() == 0:
    time.sleep(0.05)
time.sleep(0.2)   # the subscribers' side of the match
publisher.publish(msg)
print("published", flush=True)
while True:       # stays in the graph (its node name is what the run reports) until ended
    rclpy.spin_once(node, timeout_sec=0.5)
"""


class Intruder:
    """A node of nobody's run, in a run's ROS domain: a process of its own (so that its DDS
    set-up does not depend on what this test process ran before), advertising ``topic`` and
    publishing one forged message on it once a subscriber of the run matched it. The run may
    stop at either: its graph watch sees the foreign publisher (about a second after discovery),
    or its nodes take the forged message; both name the topic and the intruder."""

    def __init__(self, domain_id, topic):
        self.proc = subprocess.Popen(
            [sys.executable, "-c", INTRUDER, str(domain_id), topic,
             str(Path(__file__).resolve().parent)],
            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        self.lines = []   # (line, monotonic time it arrived)
        threading.Thread(target=self._read, daemon=True).start()

    def _read(self):
        for line in self.proc.stdout:
            self.lines.append((line.strip(), time.monotonic()))

    def wait_for(self, word, alive, hang_s=240.0):
        """Monotonic time the intruder said ``word`` ('advertised', 'published'), or None when
        ``alive()`` turned false or the intruder ended first. No deadline but a hang guard:
        start-up and discovery take what they take on a loaded machine."""
        deadline = time.monotonic() + hang_s
        while True:
            said = [t for line, t in self.lines if line == word]
            if said:
                return said[0]
            if not alive() or self.proc.poll() is not None:
                return None
            assert time.monotonic() < deadline, "the intruder hangs"
            time.sleep(0.02)

    def close(self):
        if self.proc.poll() is None:
            self.proc.kill()
        _, err = self.proc.communicate()
        return err


def _forged(topic):
    """(message, QoS) an intruder sends on ``topic``."""
    from diagnostic_msgs.msg import DiagnosticArray
    from rosgraph_msgs.msg import Clock

    from motoflex_ros.nodes.conversions import points_msg
    from motoflex_ros.nodes.qos_profiles import latched_qos, reliable_qos
    from motoflex_ros.nodes.result_messages import identification_statuses
    from motoflex_ros.nodes.stamps import time_msg
    if topic == "/clock":
        return Clock(clock=time_msg(10**12)), reliable_qos()
    if topic == "/identification/results":
        statuses = identification_statuses(COMPONENT, {"static": {"k": 1.0}})
        return DiagnosticArray(status=statuses), latched_qos()
    return points_msg(0, "swingarm_clamp", [[0.5, 0.01, 0.0]] * 3), reliable_qos()


@pytest.mark.parametrize("faults", [(f"/bench/{COMPONENT}/markers/true", "/clock"),
                                    ("/identification/results", "SIGTERM")],
                         ids=["bench-and-clock", "results-and-sigterm"])
def test_foreign_publishers_fail_runs(tmp_path, faults):
    """Two campaigns at once, each with a fault: a foreign publisher on a topic (named in the
    message as the foreign node and the topic), or SIGTERM of the campaign itself. The fault's
    moment is when the intruder's publisher exists (its discovery is part of the run's
    reaction: the graph watch or the forged message, whichever comes first)."""
    runs = Run.together(tmp_path, len(faults))
    intruders = {}
    try:
        for run, fault in zip(runs, faults):
            if fault == "SIGTERM":
                run.fault()
                run.proc.send_signal(signal.SIGTERM)
            else:
                intruders[fault] = Intruder(run.domain_id(), fault)
        for run, fault in zip(runs, faults):
            if fault in intruders:
                advertised = intruders[fault].wait_for("advertised", lambda r=run: True)
                assert advertised is not None, intruders[fault].close()
                run.fault()
                run.fault_at = advertised
        for run, fault in zip(runs, faults):
            run.assert_failed_cleanly("interrupted by SIGTERM" if fault == "SIGTERM" else
                                      f"foreign publisher on {fault}: node '/intruder'")
    finally:
        for intruder in intruders.values():
            intruder.close()


def test_vehicle_simulator_takes_results_only_from_its_identification(tmp_path):
    """Forged results (stiffness x 0.01 made the printed motorcycle unstable): refused."""
    from motoflex_ros.launcher.domain import DomainLock
    from motoflex_ros.launcher.graph import NodeGraph, NodeSpec
    with DomainLock() as lock:
        graph = NodeGraph([NodeSpec("vehicle_simulator")], lock.domain_id, tmp_path).start()
        intruder = Intruder(lock.domain_id, "/identification/results")
        try:
            start = intruder.wait_for("advertised", lambda: True)
            assert start is not None, intruder.close()
            code = graph.wait("vehicle_simulator", FAULT_S + 30.0)   # a hang guard
            assert code is not None and time.monotonic() - start < FAULT_S
        finally:
            intruder.close()
            graph.stop()
    log = (graph.log_dir / "vehicle_simulator.log").read_text()
    assert code == 2, log
    assert "foreign publisher on /identification/results: node '/intruder'" in log
    assert "Traceback" not in log


FORCED_DOMAIN = """import sys
from motoflex_ros.launcher import run
class Forced:  # the run's domain lock, forced onto a domain in use
    domain_id = int(sys.argv[1])
    origin = "forced by the test"
    def __init__(self, *args, **kwargs): pass
    def __enter__(self): return self
    def __exit__(self, *exc): pass
run.DomainLock = Forced
from motoflex_ros.cli.main import main
sys.exit(main(sys.argv[2:]))
"""


def test_two_runs_in_one_domain(tmp_path):
    """A second campaign forced into a running one's domain (it used to die with "KeyError: 8"
    in identification) stops at once, naming the first run's node as a foreign publisher. The
    first run accepts nothing of it: it fails the same way if it saw the second run's
    publishers in time, or else ends with exactly the offline campaign's results."""
    from test_campaign_graph import _assert_same, offline_identification, without_inputs
    (tmp_path / "a").mkdir()
    (tmp_path / "b").mkdir()
    first = Run(tmp_path / "a").running()
    second = Run(tmp_path / "b", forced_domain=first.domain_id())
    deadline = time.monotonic() + 60.0
    while not list((tmp_path / "b").glob("motoflex_campaign_*/log")):   # its graph starts
        assert time.monotonic() < deadline and second.proc.poll() is None, second.end()
        time.sleep(0.02)
    second.fault()
    second.assert_failed_cleanly("foreign publisher on ", bag_started=False)
    code, err, _ = first.end()
    assert "Traceback" not in err
    if code != 0:
        assert "foreign publisher on " in err, err
        assert not (first.bag / "identification.json").exists()
    else:
        recorded = json.loads((first.bag / "identification.json").read_text())
        _assert_same(without_inputs(recorded), offline_identification())
    assert wait_gone(str(tmp_path), 5.0) == []


# --- bad values in messages ----------------------------------------------------------------

BAD_SAMPLE = 300   # index of the doctored message on its topic


def _doctor(msg_type, data, fault):
    """The CDR ``data`` of a bench message with ``fault`` applied."""
    from rclpy.serialization import deserialize_message, serialize_message
    msg = deserialize_message(data, msg_type)
    if fault == "nan_load":
        msg.wrench.force.y = math.nan
    elif fault == "huge_load":
        msg.wrench.force.y = 1e9
    elif fault == "inf_marker":
        msg.poses[1].position.z = math.inf
    elif fault == "backwards_stamp":
        msg.header.stamp.sec -= 1
    return serialize_message(msg)


FAULTS = {  # fault: (topic leaf, message type name, expected text)
    "nan_load": ("load", "WrenchStamped", f"sample {BAD_SAMPLE} (stamp "),
    "huge_load": ("load", "WrenchStamped", "wrench.force.y = 1e+09 N is beyond the protocol's "
                  "range"),
    "inf_marker": ("markers/measured", "PoseArray", "poses[1].position.z = inf is not a "
                   "finite number"),
    "backwards_stamp": ("load", "WrenchStamped", "header.stamp = "),
}


def _doctored_bag(tmp_path, fault, samples=BAD_SAMPLE + 100):
    """The first ``samples`` messages of each swingarm topic of bags/example (the /clock until
    then), one message doctored; returns the bag directory."""
    import geometry_msgs.msg
    leaf, type_name, _ = FAULTS[fault]
    msg_type = getattr(geometry_msgs.msg, type_name)
    bench = f"/bench/{COMPONENT}/"
    info = mcap_bag.bag_info(EXAMPLE)
    topics = [t for t in info.topics if t.name == "/clock" or t.name.startswith(bench)]
    out = tmp_path / f"bag_{fault}"
    counts = {}
    with mcap_bag.BagWriter(out) as writer:
        for t in topics:
            writer.add_topic(t.name, t.type)
        for m in mcap_bag.read_messages(EXAMPLE, topics=[t.name for t in topics]):
            k = counts[m.topic] = counts.get(m.topic, -1) + 1
            if k >= samples or m.topic == "/clock" and counts.get(bench + "load", 0) >= samples:
                continue
            data = m.data
            if m.topic == bench + leaf and k == BAD_SAMPLE:
                data = _doctor(msg_type, data, fault)
            writer.write(m.topic, m.log_time_ns, data)
    return out


def test_bad_message_values_fail_run_at_once(tmp_path):
    """Replayed into a fresh identification node (the first node to read them), a NaN or 1e9 N
    load, an infinite marker or a stamp that goes back stop the run, naming topic, field and
    sample; no result file. The four replays run at the same time."""
    procs = {}
    for fault in FAULTS:
        folder = tmp_path / fault
        folder.mkdir()
        procs[fault] = subprocess.Popen(
            [sys.executable, "-m", "motoflex_ros.cli.main", "replay",
             str(_doctored_bag(folder, fault)), "--identify", str(folder / "identified.json"),
             "--allow-incomplete"],   # an excerpt of a run, so without status.json
            text=True, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
            env=dict(os.environ, TMPDIR=str(folder)))
    start = time.monotonic()
    for fault, proc in procs.items():
        leaf, _, expected = FAULTS[fault]
        try:
            _, err = proc.communicate(timeout=120)
        finally:
            if proc.poll() is None:
                proc.kill()
                proc.communicate()
        assert proc.returncode != 0, (fault, err)
        assert f"/bench/{COMPONENT}/{leaf}: sample {BAD_SAMPLE} (stamp " in err, (fault, err)
        assert expected in err and "Traceback" not in err, (fault, err)
        assert not (tmp_path / fault / "identified.json").exists()
    assert time.monotonic() - start < 60.0   # start-up, a few hundred samples, the fault
    assert _our_processes(str(tmp_path)) == []
