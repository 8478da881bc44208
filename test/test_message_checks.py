"""Message values and publisher trust, without ROS processes (issue 13, points 2 and 6).

The graph-level cases (a running campaign, a replayed bag) are in test_faults.py.
"""
import json
import math
from types import SimpleNamespace

import pytest

pytest.importorskip("rclpy")
from motoflex_ros.formats.component_file import load_component  # noqa: E402
from motoflex_ros.nodes.cdr import points_cdr, wrench_cdr  # noqa: E402
from motoflex_ros.nodes.endpoints import ForeignPublisher, InputGuard, RunEndpoints  # noqa: E402
from motoflex_ros.nodes.message_checks import BadMessage, BenchInputs  # noqa: E402

LOAD = "/bench/swingarm/load: sample"


def _inputs():
    return BenchInputs("swingarm", 150.0)


def test_good_messages_pass_unchanged():
    checked = _inputs()
    assert checked.load(wrench_cdr(5, "c", -150.0)) == (5, -150.0)
    assert checked.load(wrench_cdr(5, "c", 20.0)) == (5, 20.0)   # the same stamp again: ok
    ns, points = checked.markers("markers/true", points_cdr(7, "c", [[1.0, 2.0, 3.0]]))
    assert ns == 7 and points.tolist() == [[1.0, 2.0, 3.0]]
    assert checked.markers("markers/measured", points_cdr(7, "c", []))[1].shape == (0, 3)


@pytest.mark.parametrize("force, expected", [
    (math.nan, f"{LOAD} 1 (stamp 0.000000002 s): wrench.force.y = nan is not a finite number"),
    (-math.inf, "wrench.force.y = -inf is not a finite number"),
    (1e9, "wrench.force.y = 1e+09 N is beyond the protocol's range (|F_y| <= 150 N)"),
    (-150.001, "is beyond the protocol's range"),
])
def test_bad_loads_refused_naming_topic_field_sample(force, expected):
    checked = _inputs()
    checked.load(wrench_cdr(1, "c", 0.0))
    with pytest.raises(BadMessage, match="message refused, run stopped") as err:
        checked.load(wrench_cdr(2, "c", force))
    assert expected in str(err.value)


def test_moment_loads_pass_as_torque_and_are_bounded():
    """Issue 22: a moment test's load is the WrenchStamped torque; |M| within the protocol's
    moments, a torque where the protocol has no moment test refused by name."""
    from rclpy.serialization import serialize_message

    from motoflex_ros.bench.actuator import LoadSample
    from motoflex_ros.nodes.cdr import phase_cdr, sample_from_phase, wrench_vector_from_cdr
    from motoflex_ros.nodes.conversions import wrench_msg
    unit = (0.0, 0.0, 0.0, 0.6, 0.0, -0.8)
    sample = LoadSample(3, 0.5, 1e-3, 40.0, "moment_axial", "static", "hold", 0.0, False, unit)
    data = wrench_cdr(5, "c", sample.wrench_vector)
    reference = bytes(serialize_message(wrench_msg(5, "c", sample.wrench_vector)))
    assert wrench_vector_from_cdr(reference) == wrench_vector_from_cdr(data)
    checked = BenchInputs("swingarm", 150.0, load_limit_nm=60.0)
    ns, load = checked.wrench(data)
    assert ns == 5 and load == (0.0, 0.0, 0.0, 24.0, 0.0, -32.0)
    back, _ = sample_from_phase(phase_cdr(sample), load)
    assert back.wrench == unit and back.force == pytest.approx(40.0, rel=1e-15)
    with pytest.raises(BadMessage, match=r"wrench.torque = \|M\| = 40 N m is beyond the "
                                         r"protocol's range \(\|M\| <= 0 N m\)"):
        _inputs().wrench(data)


def test_markers_not_finite_refused_with_index_and_axis():
    checked = _inputs()
    with pytest.raises(BadMessage) as err:
        checked.markers("markers/true", points_cdr(3, "c", [[0, 0, 0], [0, math.nan, 0]]))
    assert ("/bench/swingarm/markers/true: sample 0 (stamp 0.000000003 s): "
            "poses[1].position.y = nan is not a finite number") in str(err.value)


def test_stamps_going_back_refused_per_topic():
    checked = _inputs()
    checked.load(wrench_cdr(2_000_000_000, "c", 0.0))
    checked.markers("markers/true", points_cdr(1_000_000_000, "c", []))   # another topic: ok
    with pytest.raises(BadMessage) as err:
        checked.load(wrench_cdr(1_999_999_999, "c", 0.0))
    assert (f"{LOAD} 1 (stamp 1.999999999 s): header.stamp = 1.999999999 s goes back from "
            f"2.000000000 s") in str(err.value)


def test_load_limit_is_the_protocols_largest_load_with_margin():
    from motoflex_ros.bench.offline_campaign import setup_campaign
    from motoflex_ros.bench.plan import LOAD_MARGIN
    plan = setup_campaign(load_component("swingarm")).plan
    largest = max(abs(t.amplitude_n) for t in plan.tests)
    assert plan.load_limit_n == pytest.approx(LOAD_MARGIN * largest) and largest > 0


class _Sub:
    def __init__(self, topic_name):
        self.topic_name = topic_name


class _Node:
    """What the guard uses of a node: a logger and the graph's publisher endpoints."""

    def __init__(self, endpoints=()):
        self.errors = []
        self.endpoints = list(endpoints)

    def get_logger(self):
        return SimpleNamespace(error=self.errors.append)

    def get_publishers_info_by_topic(self, topic):
        return self.endpoints


def test_guard_accepts_the_runs_publishers_and_refuses_others(tmp_path):
    ours, theirs = bytes(range(16)), bytes(range(1, 17))
    (tmp_path / "load_actuator.json").write_text(json.dumps({ours.hex(): "/clock"}))
    foreign = SimpleNamespace(endpoint_gid=list(theirs), node_name="intruder",
                              node_namespace="/")
    guard = InputGuard(_Node([foreign]), RunEndpoints(tmp_path))
    sub = _Sub("/clock")
    guard.check(sub, ours, 1)
    with pytest.raises(ForeignPublisher) as err:
        guard.check(sub, theirs, 1)
    assert str(err.value).startswith("foreign publisher on /clock: node '/intruder' (GID "
                                     "01.02.03")
    # a publisher written down after the guard last read the folder: found on a second read
    (tmp_path / "recorder.json").write_text(json.dumps({theirs.hex(): "/clock"}))
    guard.check(sub, theirs, 2)


def test_guard_only_from_names_the_node_it_refuses(tmp_path):
    results, other = bytes(16), bytes(range(16))
    (tmp_path / "identification.json").write_text(json.dumps({results.hex(): "/r"}))
    (tmp_path / "bag_replay.json").write_text(json.dumps({other.hex(): "/r"}))
    guard = InputGuard(_Node(), RunEndpoints(tmp_path))
    sub = _Sub("/r")
    guard.only_from(sub, ("identification",))
    guard.check(sub, results, 1)
    with pytest.raises(ForeignPublisher, match="node 'bag_replay' of this run published here; "
                                               "only identification may"):
        guard.check(sub, other, 1)


def test_guard_counts_a_late_subscription_from_its_first_message():
    """A recorder that discovers a topic of a running graph (an empty ``topics`` list) gets a
    publisher's messages from sequence number N > 1: not N - 1 lost (which made a hand-started
    recorder exit 3), but a gap after that is; on a subscription made before its publisher
    began, a first number above 1 is a loss."""
    node = _Node()
    guard = InputGuard(node, None)
    late, early = _Sub("/bench/frame/load"), _Sub("/clock")
    guard.joined_late.add(late)
    a, b = bytes(16), bytes(range(16))
    for sub, gid, seq in ((late, a, 5), (late, a, 6), (late, b, 40), (late, a, 9)):
        guard.check(sub, gid, seq)
    assert guard.gaps == 2 and len(node.errors) == 1 and "6 -> 9" in node.errors[0]
    guard.check(early, a, 3)
    assert guard.gaps == 4
