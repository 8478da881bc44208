"""Shipped node parameter files and the message conversions (no ROS graph needed)."""
import math
from pathlib import Path

import numpy as np
import pytest
import yaml

pytest.importorskip("rclpy")
import rclpy  # noqa: E402
from rclpy.serialization import deserialize_message, serialize_message  # noqa: E402
from scipy.spatial.transform import Rotation  # noqa: E402

from motoflex_ros.nodes import cdr, conversions, result_messages, stamps  # noqa: E402
from motoflex_ros.spatial import quaternion_xyzw  # noqa: E402

CONFIG = Path(conversions.__file__).resolve().parents[1] / "config" / "nodes"
from motoflex_ros.nodes import NODE_CLASSES as NODES  # noqa: E402
from motoflex_ros.nodes.params import parameters_yaml  # noqa: E402


@pytest.mark.parametrize("name", sorted(NODES))
def test_nodes_config_file_is_written_from_the_declarations(name):
    """One source (issue 24, point 8): the shipped file is what the node's PARAMS give, so
    its comments say the ranges the node enforces (noise: [-1, 0.001], not [-1, 1]);
    tools/write_node_configs.py rewrites them."""
    import importlib
    node_class = getattr(importlib.import_module(f"motoflex_ros.nodes.{name}"), NODES[name])
    assert (CONFIG / f"{name}.yaml").read_text() == parameters_yaml(name, node_class.PARAMS)
    noise = next((p for p in node_class.PARAMS if p.name == "noise"), None)
    if noise is not None:
        assert f"(float in [-1, {noise.high:g}])" in (CONFIG / f"{name}.yaml").read_text()


@pytest.mark.parametrize("name", sorted(NODES))
def test_nodes_config_defaults_roundtrip(name):
    """The shipped file holds the declared defaults, and rcl parses it into those values."""
    import importlib
    node_class = getattr(importlib.import_module(f"motoflex_ros.nodes.{name}"), NODES[name])
    path = CONFIG / f"{name}.yaml"
    values = yaml.safe_load(path.read_text())[name]["ros__parameters"]
    declared = {p.name: p for p in node_class.PARAMS}
    assert set(values) <= set(declared)
    for key, value in values.items():
        default = declared[key].default
        assert declared[key].check(name, value) == default, key
    missing = {k for k in declared if k not in values}
    assert all(declared[k].default == () for k in missing), missing
    context = rclpy.Context()
    rclpy.init(args=["x", "--ros-args", "--params-file", str(path)], context=context)
    try:
        node = rclpy.create_node(name, context=context)
        parsed = {k: p.value for k, p in node._parameter_overrides.items()}
        node.destroy_node()
    finally:
        rclpy.shutdown(context=context)
    assert {k: tuple(v) if isinstance(v, list) else v for k, v in parsed.items()} == {
        k: tuple(v) if isinstance(v, list) else v for k, v in values.items()}


@pytest.mark.parametrize("rotvec", [(0.0, 0.0, 0.0), (1e-4, 2e-4, -3e-4), (3.0, 0.1, 0.0),
                                    (0.0, 3.1, 0.2), (0.1, 0.0, 3.1), (1.0, 1.0, 1.0)])
def test_nodes_quaternion_scipy(rotvec):
    rot = Rotation.from_rotvec(rotvec)
    q = np.array(quaternion_xyzw(rot.as_matrix()))
    ref = rot.as_quat()
    assert min(np.abs(q - ref).max(), np.abs(q + ref).max()) < 1e-15
    assert math.isclose(np.linalg.norm(q), 1.0, rel_tol=1e-15)


def test_nodes_phase_and_points_roundtrip():
    from geometry_msgs.msg import PoseArray
    from std_msgs.msg import String

    from motoflex_ros.bench.actuator import LoadSample
    sample = LoadSample(7, 0.1 + 1 / 603.1802138593138, 1 / 603.1802138593138, -12.5e-3,
                        "sweep_03", "sweep", "steady", 104.0, False)
    msg = deserialize_message(serialize_message(conversions.phase_msg(sample)), String)
    assert cdr.sample_from_phase(msg, sample.force) == (sample, None)
    end = conversions.phase_msg(end_ns=123456789)
    assert cdr.sample_from_phase(end, 0.0) == (None, 123456789)
    points = np.random.default_rng(1).normal(size=(8, 3)) * 1e-3
    wire = deserialize_message(serialize_message(conversions.points_msg(5, "f", points)),
                               PoseArray)
    assert np.array_equal(conversions.points_from_msg(wire), points)


def test_nodes_identification_statuses_roundtrip():
    """identify-format results -> DiagnosticStatus KeyValues -> the same results, exactly."""
    from diagnostic_msgs.msg import DiagnosticArray

    from motoflex_ros.bench.offline_campaign import identify_components
    from motoflex_ros.formats.component_file import load_components
    from motoflex_ros.formats.json_yaml import to_jsonable
    from motoflex_ros.study.identified_variants import carried_inertias
    components = load_components(["swingarm"])   # with the principal hinges
    carried = carried_inertias(components)
    runs = identify_components(components, seed=0, carried=carried)
    result = to_jsonable(runs["swingarm"][1].identification.to_dict())
    assert result["principal"]["identified"]
    array = DiagnosticArray(status=result_messages.identification_statuses("swingarm", result))
    wire = deserialize_message(serialize_message(array), DiagnosticArray)
    names = [s.name for s in wire.status]
    assert names[0] == "swingarm/split" and "swingarm/static" in names
    assert result_messages.results_from_statuses(wire.status) == {"swingarm": result}


@pytest.mark.parametrize("n, frame_id", [(0, ""), (1, "a"), (4, "swingarm_clamp"),
                                         (8, "frame_clamp"), (5, "abc")])
def test_nodes_points_cdr_roundtrip(n, frame_id):
    """The CDR fast path against rclpy's serializer, both ways (padding bytes aside: Fast CDR
    leaves them uninitialised, so the byte strings are compared through the decoders)."""
    from geometry_msgs.msg import PoseArray
    points = np.random.default_rng(n).normal(size=(n, 3))
    ns = 1_234_567_890_123
    ours = cdr.points_cdr(ns, frame_id, points)
    ref = serialize_message(conversions.points_msg(ns, frame_id, points))
    assert len(ours) == len(ref)
    decoded = deserialize_message(ours, PoseArray)
    assert decoded.header.frame_id == frame_id
    assert stamps.time_ns(decoded.header.stamp) == ns
    assert np.array_equal(conversions.points_from_msg(decoded), points)
    assert all((p.orientation.x, p.orientation.y, p.orientation.z, p.orientation.w)
               == (0.0, 0.0, 0.0, 1.0) for p in decoded.poses)
    stamp, back = cdr.points_from_cdr(ref)
    assert stamp == ns and np.array_equal(back, points)


@pytest.mark.parametrize("frame_id", ["", "a", "frame_clamp", "swingarm_clamp", "abc"])
def test_nodes_bench_cdr_roundtrip(frame_id):
    """The phase, load and pose fast paths against rclpy's serializer, both ways: the same
    length, our bytes decode to the message-object path's values, exactly, and our readers
    decode rclpy's bytes."""
    from geometry_msgs.msg import PoseStamped, WrenchStamped
    from std_msgs.msg import String

    from motoflex_ros.bench.actuator import LoadSample
    ns, force = 1_234_567_890_123, -12.5e-3 / 3.0
    ours = cdr.wrench_cdr(ns, frame_id, force)
    ref = serialize_message(conversions.wrench_msg(ns, frame_id, force))
    assert len(ours) == len(ref)
    assert deserialize_message(ours, WrenchStamped) == deserialize_message(ref, WrenchStamped)
    assert cdr.wrench_from_cdr(ref) == cdr.wrench_from_cdr(ours) == (ns, force)

    rotation = Rotation.from_rotvec([1e-3, -2e-3, 0.5e-3]).as_matrix()
    position = np.array([0.1, -0.2, 0.3]) / 7.0
    ours = cdr.pose_cdr(ns, frame_id, position, rotation)
    ref = serialize_message(conversions.pose_msg(ns, frame_id, position, rotation))
    assert len(ours) == len(ref)
    assert deserialize_message(ours, PoseStamped) == deserialize_message(ref, PoseStamped)

    sample = LoadSample(7, 0.1 + 1 / 603.1802138593138, 1 / 603.1802138593138, force,
                        f"sweep_03{frame_id}", "sweep", "steady", 104.0, False)
    for ours, ref in [(cdr.phase_cdr(sample), conversions.phase_msg(sample)),
                      (cdr.phase_cdr(end_ns=ns), conversions.phase_msg(end_ns=ns))]:
        assert deserialize_message(ours, String) == ref
        assert cdr.phase_text(serialize_message(ref)) == ref.data
        assert cdr.sample_from_phase(ours, force) == \
            cdr.sample_from_phase(ref, force)
        assert cdr.is_end_marker(ours) == cdr.is_end_marker(ref)
    assert cdr.sample_from_phase(cdr.phase_cdr(sample), force) == (sample, None)
    assert cdr.is_end_marker(cdr.phase_cdr(end_ns=ns))
