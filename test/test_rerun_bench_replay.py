"""The deformed beam in the recording moves as the component simulator moved the bench.

The frame's bench topics of the recorded example campaign (bags/example, made by the node
graph: load_actuator -> component_simulator) are copied into a bag of their own and converted.
The loaded end of the drawn structure must sit where the simulator's true markers put it
(rigid fit of /bench/frame/markers/true), at every drawn sample, harmonic ones at resonance
included; the quasi-static K^-1 f of the same load does not.
"""
import json
from pathlib import Path

import numpy as np
import pytest

from motoflex_ros.formats.component_file import load_component
from motoflex_ros.record.mcap_bag import BagWriter, read_messages
from motoflex_ros.record.rerun_bag import convert_bag, decode
from motoflex_ros.record.rerun_readback import component_rows

EXAMPLE = Path(__file__).resolve().parents[1] / "bags" / "example"
TOPICS = ("/bench/frame/load", "/bench/frame/phase", "/bench/frame/markers/true")
FLOAT32_M = 1e-6     # rerun stores positions as float32 (about 6e-8 m at 1 m)


def _copy_bench(bag):
    """The frame's load, phase and true-marker messages of the example, in recording order."""
    with BagWriter(bag) as writer:
        for message in read_messages(EXAMPLE, TOPICS):
            writer.add_topic(message.topic, message.type)
            writer.write(message.topic, message.log_time_ns, message.data)


def _stamped(bag, topic):
    out = {}
    for message in read_messages(bag, [topic]):
        msg = decode(message)
        out[msg.header.stamp.sec * 10**9 + msg.header.stamp.nanosec] = msg
    return out


def _true_end_displacements(bag, q0):
    """{stamp [ns]: loaded-end displacement [m]} of the simulator's true markers (rigid fit
    to the markers of the first sample, a test start from rest under zero load)."""
    from motoflex_ros.bench.sensor import fit_pose
    markers = {t: np.array([[p.position.x, p.position.y, p.position.z] for p in m.poses])
               for t, m in _stamped(bag, "/bench/frame/markers/true").items()}
    rest = markers[min(markers)]
    return {t: fit_pose(points, rest, q0)[0] - q0 for t, points in markers.items()}


def _labels(bag):
    labels = [json.loads(decode(m).data) for m in read_messages(bag, ["/bench/frame/phase"])]
    return {int(round(d["t"] * 1e9)): d for d in labels if "end_ns" not in d}


@pytest.fixture(scope="module")
def replayed(tmp_path_factory):
    if not (EXAMPLE / "metadata.yaml").is_file():
        pytest.skip("bags/example is not in this checkout")
    bag = tmp_path_factory.mktemp("bags") / "frame_bench"
    _copy_bench(bag)
    rrd, _ = convert_bag(bag)
    return bag, rrd


def _drawn_end(rrd, q0):
    """{stamp [ns]: loaded-end position drawn [m]} and the stated exaggeration factor."""
    (_, undeformed), = component_rows(rrd, "/bench/frame/structure/undeformed",
                                      "LineStrips3D:strips")
    vertices = np.array(undeformed, float)             # (n_elements, 2, 3)
    strip, end = np.argwhere(np.linalg.norm(vertices - q0, axis=2) < FLOAT32_M)[0]
    (_, factor), = component_rows(rrd, "/bench/frame/structure", "exaggeration_factor")
    shapes = component_rows(rrd, "/bench/frame/structure", "LineStrips3D:strips", "sim_time")
    return {t: np.array(s[strip][end], float) for t, s in shapes}, factor[0]


def test_rerun_structure_follows_simulator_markers_roundtrip(replayed):
    bag, rrd = replayed
    reduced = load_component("frame").clamped_reduced()
    q0 = np.asarray(reduced.q0, float)
    truth = _true_end_displacements(bag, q0)
    drawn, factor = _drawn_end(rrd, q0)
    assert len(drawn) == 400 and set(drawn) <= set(truth)
    labels = _labels(bag)
    kinds = {labels[t]["kind"] for t in drawn}
    assert {"static", "harmonic", "sweep", "decay"} <= kinds
    for t, position in drawn.items():
        np.testing.assert_allclose(position, q0 + factor * truth[t], rtol=0, atol=FLOAT32_M)


def test_replayed_loaded_end_equals_simulator_markers_roundtrip(replayed):
    """In double precision, before drawing: the replay is the simulator's state to 1e-14 m."""
    from motoflex_ros.bench.replayed_loads import recorded_samples, replayed_displacements
    bag, _ = replayed
    component = load_component("frame")
    reduced = component.clamped_reduced()
    q0 = np.asarray(reduced.q0, float)
    truth = _true_end_displacements(bag, q0)
    loads = sorted((t, np.array([m.wrench.force.x, m.wrench.force.y, m.wrench.force.z,
                                 m.wrench.torque.x, m.wrench.torque.y, m.wrench.torque.z]))
                   for t, m in _stamped(bag, "/bench/frame/load").items())   # moment tests too
    phases = [decode(m).data for m in read_messages(bag, ["/bench/frame/phase"])]
    replay = recorded_samples(phases, loads)
    assert replay.labelled
    picks = np.arange(0, len(loads), 5)
    shapes = replayed_displacements(reduced, replay.samples, picks)
    end = int(np.argmin(np.linalg.norm(np.asarray(component.node_xyz) - q0, axis=1)))
    want = np.array([truth[loads[k][0]] for k in picks])
    np.testing.assert_allclose(shapes[:, end], want, rtol=0, atol=1e-14)
    assert np.abs(want).max() > 1e-3


def test_rerun_structure_is_not_quasi_static_at_resonance(replayed):
    """At the torsion test (74.6 Hz, the frame's first eigenfrequency) K^-1 f is far off."""
    bag, rrd = replayed
    reduced = load_component("frame").clamped_reduced()
    q0 = np.asarray(reduced.q0, float)
    truth = _true_end_displacements(bag, q0)
    labels, loads = _labels(bag), _stamped(bag, "/bench/frame/load")
    drawn, factor = _drawn_end(rrd, q0)
    resonant = [t for t in drawn if labels[t]["test"] == "torsion"
                and labels[t]["phase"] == "steady"]
    assert resonant
    worst = 0.0
    for t in resonant:
        force = loads[t].wrench.force.y
        static = reduced.static_end_motion([0.0, force, 0.0, 0.0, 0.0, 0.0])[:3]
        worst = max(worst, np.linalg.norm(static - truth[t]) / np.abs(truth[t]).max())
        np.testing.assert_allclose(drawn[t], q0 + factor * truth[t], rtol=0, atol=FLOAT32_M)
    assert worst > 1.0      # resonant motion ~ 1/(2 zeta) = 50 times the static one


def test_replay_without_phase_labels_matches_lsim():
    """No phase labels: one test from rest, linear load between stamps; scipy's lsim (its own
    discretisation of the same state space, linear input interpolation) gives the same."""
    from scipy.signal import lsim

    from motoflex_ros.bench.replayed_loads import recorded_samples, replayed_displacements
    from motoflex_ros.structures.clamped import state_space
    component = load_component("frame")
    reduced = component.clamped_reduced()
    times = np.arange(200) * 2e-3                       # 500 Hz, 0.4 s
    force = 100.0 * np.sin(2 * np.pi * 60.0 * times) * np.minimum(times / 0.1, 1.0)
    replay = recorded_samples([], [(int(round(t * 1e9)), f) for t, f in zip(times, force)])
    assert not replay.labelled
    end = int(np.argmin(np.linalg.norm(np.asarray(component.node_xyz) - reduced.q0, axis=1)))
    got = replayed_displacements(reduced, replay.samples, np.arange(len(times)))[:, end]
    a, b = state_space(reduced)
    c = np.zeros((3, a.shape[0]))
    c[np.arange(3), reduced.end_dofs[:3]] = 1.0
    _, want, _ = lsim((a, b[:, 1:2], c, np.zeros((3, 1))), force, times)
    np.testing.assert_allclose(got, want, rtol=0, atol=1e-10 * np.abs(want).max())
