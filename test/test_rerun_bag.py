"""`motoflex rerun BAG`: a recorded bag becomes bags/<run>/<run>.rrd with every entity path.

The bag is written here with the project's bag writer and CDR from the rosbags type store, with
the topics and types of issue 8; its numbers come from the shipped frame model (static response
of the clamped reduced model), so the recording is checked against the model it shows.
"""
import json

import numpy as np
import pytest
from hostile import run_motoflex

from motoflex_ros.formats.component_file import load_component
from motoflex_ros.record.mcap_bag import BagWriter
from motoflex_ros.record.rerun_readback import (
    component_rows,
    entity_rows,
    scalar_values,
    verify_text,
)
from motoflex_ros.vehicle.animation import MODE_CYCLES, MODE_FRAMES_PER_CYCLE

N_LOAD = 120
N_BODY = 50
N_SPEEDS = 18          # eig.json: 40..210 km/h in steps of 10
BAG_SPEED_STEP_KMH = 5.0
N_BAG_SPEEDS = 35      # /vehicle/eigenvalues: 40..210 km/h in steps of 5
MODE_FRAMES = MODE_FRAMES_PER_CYCLE * MODE_CYCLES
RATE_HZ = 100.0


def _ts():
    from rosbags.typesys import Stores, get_typestore
    return get_typestore(Stores.ROS2_JAZZY)


def _header(ts, t_ns, frame="frame"):
    m = ts.types
    stamp = m["builtin_interfaces/msg/Time"](sec=t_ns // 10**9, nanosec=t_ns % 10**9)
    return m["std_msgs/msg/Header"](stamp=stamp, frame_id=frame)


def _vector(ts, xyz):
    return ts.types["geometry_msgs/msg/Vector3"](x=float(xyz[0]), y=float(xyz[1]),
                                                  z=float(xyz[2]))


def _pose(ts, xyz, quat=(0.0, 0.0, 0.0, 1.0)):
    m = ts.types
    return m["geometry_msgs/msg/Pose"](
        position=m["geometry_msgs/msg/Point"](x=float(xyz[0]), y=float(xyz[1]), z=float(xyz[2])),
        orientation=m["geometry_msgs/msg/Quaternion"](x=quat[0], y=quat[1], z=quat[2],
                                                      w=quat[3]))


def _write(writer, ts, topic, type_name, t_ns, msg):
    writer.add_topic(topic, type_name)
    writer.write(topic, t_ns, bytes(ts.serialize_cdr(msg, type_name)))


def _bench(writer, ts, reduced):
    m = ts.types
    for i in range(N_LOAD):
        t_ns = int(i * 1e9 / RATE_HZ)
        force = 100.0 * i / (N_LOAD - 1)
        motion = reduced.static_end_motion([0, force, 0, 0, 0, 0])
        q = reduced.q0 + motion[:3]
        wrench = m["geometry_msgs/msg/Wrench"](force=_vector(ts, [0, force, 0]),
                                               torque=_vector(ts, [0, 0, 0]))
        _write(writer, ts, "/bench/frame/load", "geometry_msgs/msg/WrenchStamped", t_ns,
               m["geometry_msgs/msg/WrenchStamped"](header=_header(ts, t_ns), wrench=wrench))
        _write(writer, ts, "/bench/frame/pose", "geometry_msgs/msg/PoseStamped", t_ns,
               m["geometry_msgs/msg/PoseStamped"](header=_header(ts, t_ns), pose=_pose(ts, q)))
        markers = [_pose(ts, q + d) for d in np.eye(3) * 0.05]
        for kind in ("true", "measured"):
            _write(writer, ts, f"/bench/frame/markers/{kind}", "geometry_msgs/msg/PoseArray",
                   t_ns, m["geometry_msgs/msg/PoseArray"](header=_header(ts, t_ns),
                                                          poses=markers))


def _identification(writer, ts, reduced):
    m = ts.types
    static = reduced.static_lateral(100.0)
    values = {"l": static.axis.l, "beta": static.axis.beta, "b": static.axis.b, "k": static.k}
    status = m["diagnostic_msgs/msg/DiagnosticStatus"](
        level=b"\x00"[0], name="frame/static", message="identified", hardware_id="bench",
        values=[m["diagnostic_msgs/msg/KeyValue"](key=k, value=repr(float(v)))
                for k, v in values.items()])
    t_ns = int(N_LOAD * 1e9 / RATE_HZ)
    _write(writer, ts, "/identification/results", "diagnostic_msgs/msg/DiagnosticArray", t_ns,
           m["diagnostic_msgs/msg/DiagnosticArray"](header=_header(ts, t_ns), status=[status]))
    return values


def lumped_motorcycle(static):
    """The touring motorcycle with the frame's identified static joint (the core's model the
    vehicle_simulator builds from these results)."""
    from motoflex_ros.config import resolve_config
    from motoflex_ros.study.identified_variants import build_variant
    from motoflex_ros.vehicle.model import load_vehicle
    rigid = load_vehicle(resolve_config("vehicles", "touring"))
    return build_variant(rigid, "static", ["frame"], {"frame": {"static": static}},
                         {"frame": load_component("frame")})


def lumped_sweep(static):
    """Speeds [m/s] and the core's modal sweep of :func:`lumped_motorcycle`."""
    from motoflex_ros.vehicle.linearize import linearize
    from motoflex_ros.vehicle.modes import modal_sweep
    speeds = np.arange(40.0, 210.0 + 1e-9, BAG_SPEED_STEP_KMH) / 3.6
    return speeds, modal_sweep(linearize(lumped_motorcycle(static)), speeds)


def _write_ros(writer, topic, type_name, t_ns, msg):
    """A message as the nodes publish it (rclpy's CDR)."""
    from rclpy.serialization import serialize_message
    writer.add_topic(topic, type_name)
    writer.write(topic, t_ns, bytes(serialize_message(msg)))


def _vehicle_outputs(writer, static, eigenvalues):
    """The vehicle_simulator's latched outputs, encoded by the node's own conversions: joint
    axes of the lumped motorcycle and (``eigenvalues``) its eigenvalues over speed."""
    from diagnostic_msgs.msg import DiagnosticArray

    from motoflex_ros.nodes.conversions import axis_marker
    from motoflex_ros.nodes.result_messages import mode_statuses
    revolute = [j for j in lumped_motorcycle(static).joints if j.kind == "revolute"]
    for k, joint in enumerate(revolute):
        _write_ros(writer, "/vehicle/joint_axes", "visualization_msgs/msg/Marker", 10**9,
                   axis_marker(k, "vehicle", joint.name, joint.point, joint.axis))
    if eigenvalues:
        speeds, sweep = lumped_sweep(static)
        _write_ros(writer, "/vehicle/eigenvalues", "diagnostic_msgs/msg/DiagnosticArray",
                   10**9, DiagnosticArray(status=mode_statuses(speeds, sweep.modes)))


def _road_test(writer, ts):
    m = ts.types
    for i in range(N_BODY):
        t_ns = int((2.0 + i / RATE_HZ) * 1e9)
        steer = 0.01 * np.sin(2 * np.pi * i / N_BODY)
        _write(writer, ts, "/vehicle/joint_states", "sensor_msgs/msg/JointState", t_ns,
               m["sensor_msgs/msg/JointState"](header=_header(ts, t_ns), name=["steer", "roll"],
                                               position=np.array([steer, 0.5 * steer]),
                                               velocity=np.zeros(2), effort=np.zeros(2)))
        poses = [_pose(ts, [30.0 * i / RATE_HZ + dx, 0.0, 0.5]) for dx in (0.0, 0.7, 1.4)]
        _write(writer, ts, "/vehicle/bodies", "geometry_msgs/msg/PoseArray", t_ns,
               m["geometry_msgs/msg/PoseArray"](header=_header(ts, t_ns), poses=poses))


def _identification_file(path, reduced, static):
    """identification.json as the campaign writes it: static test, mode axes, a 2-step sweep."""
    modes = {label: reduced.mode_axis(label) for label in ("torsion", "bending")}
    result = {"static": static,
              **{label: {"l": a.l, "beta": a.beta, "b": a.b} for label, a in modes.items()},
              "k_t": 1.0e6, "k_b": 2.0e6,
              "principal": {"identified": True, "hinges": [   # issue 22: drawn beside them
                  {"l": static["l"], "beta": static["beta"] + 0.2, "b": static["b"],
                   "k": 1.0e6}]},
              "sweep": [{"f_hz": f, "l": static["l"], "beta": static["beta"] + 0.01 * f,
                         "b": static["b"]} for f in (1.0, 20.0)]}
    (path / "identification.json").write_text(json.dumps({"frame": result}))


def make_bag(path, with_results=False, eigenvalues=True):
    """A small run bag with the rig's topics; returns the identified static values it holds.

    The vehicle_simulator's joint axes and (``eigenvalues``) /vehicle/eigenvalues are those of
    the lumped motorcycle of these values. ``with_results`` adds the run folder's result
    files: identification.json and eig.json (from ``motoflex eig`` on the rigid touring
    motorcycle, as the report writes it).
    """
    ts = _ts()
    reduced = load_component("frame").clamped_reduced()
    with BagWriter(path) as writer:
        _bench(writer, ts, reduced)
        values = _identification(writer, ts, reduced)
        _road_test(writer, ts)
        _vehicle_outputs(writer, values, eigenvalues)
    if with_results:
        _identification_file(path, reduced, values)
        eig = run_motoflex(["eig", "--vehicle", "touring", "--range-kmh", "40", "210",
                            "--step-kmh", "10", "--json"])
        assert eig.returncode == 0, eig.stderr
        (path / "eig.json").write_text(eig.stdout)
    return values


@pytest.fixture(scope="module")
def converted(tmp_path_factory):
    bag = tmp_path_factory.mktemp("bags") / "run1"
    values = make_bag(bag, with_results=True)
    result = run_motoflex(["rerun", bag])
    assert result.returncode == 0, result.stderr
    return bag, values, result.stdout


def test_rerun_bag_writes_rrd_that_verifies(converted):
    bag, _, stdout = converted
    rrd = bag / "run1.rrd"
    assert rrd.is_file()
    assert str(rrd) in stdout
    assert "1 file verified without error." in verify_text(rrd)
    assert not list(bag.glob(".*.tmp"))


def test_rerun_bag_roundtrip_entity_counts(converted):
    bag, _, _ = converted
    rows = entity_rows(bag / "run1.rrd")
    expected = {
        "/bench/frame/load": N_LOAD,
        "/bench/frame/load/force": N_LOAD,
        "/bench/frame/load/end_displacement": N_LOAD,
        "/bench/frame/structure": N_LOAD,
        "/bench/frame/markers/true": N_LOAD,
        "/bench/frame/markers/measured": N_LOAD,
        "/identification/frame/static/l": 1,
        "/identification/frame/static/beta": 1,
        "/identification/frame/static/b": 1,
        "/identification/frame/static/k": 1,
        "/vehicle/road_test/joints/steer": N_BODY,
        "/vehicle/road_test/joints/roll": N_BODY,
        "/vehicle/road_test/body0": N_BODY,
        "/vehicle/road_test/body2": N_BODY,
        "/vehicle/eigenvalues/weave/real_part": N_BAG_SPEEDS,
        "/vehicle/eigenvalues/wobble/frequency_hz": N_BAG_SPEEDS,
        "/vehicle/eigenvalues/capsize/real_part": N_BAG_SPEEDS,
        "/identification/frame/decomposition/k_t": 1,
        "/vehicle/modes/weave/frame": MODE_FRAMES,
        "/vehicle/modes/weave/front_wheel": MODE_FRAMES,
        "/vehicle/modes/wobble/upper_fork": MODE_FRAMES,
    }
    for path, count in expected.items():
        assert rows.get(path, 0) == count, (path, rows.get(path))
    assert "/vehicle/road_test/frame" not in rows     # the bag's road test, not the model's
    assert "/vehicle/eigenvalues/all/real_part" not in rows   # the bag's, not eig.json's
    static = entity_rows(bag / "run1.rrd", static=True)
    for path in ("/bench/frame", "/bench/frame/structure/undeformed",
                 "/bench/frame/structure/clamps", "/bench/frame/structure/load_point",
                 "/bench/frame/structure/exaggeration", "/bench/frame/axes/static",
                 "/bench/frame/axes/static/joint", "/bench/frame/axes/torsion",
                 "/bench/frame/axes/bending", "/bench/frame/axes/sweep",
                 "/bench/frame/axes/principal_1", "/bench/frame/axes/principal_1/joint",
                 "/vehicle/eigenvalues/model"):
        assert static.get(path, 0) >= 1, path
    # one marker per revolute joint, its id the joint's place among them (the lumped hinge
    # comes after the mechanism's revolute joints)
    assert any(path.startswith("/vehicle/joint_axes/frame_static/") for path in static), static


def test_rerun_bag_eigenvalues_roundtrip(converted):
    """The series are the bag's /vehicle/eigenvalues: the core's sweep of the lumped model."""
    bag, values, _ = converted
    speeds, sweep = lumped_sweep(values)
    rrd = bag / "run1.rrd"
    for mode in ("weave", "wobble", "capsize"):
        want = sweep.modes[mode]
        real = scalar_values(rrd, f"/vehicle/eigenvalues/{mode}/real_part")
        freq = scalar_values(rrd, f"/vehicle/eigenvalues/{mode}/frequency_hz")
        assert len(real) == len(freq) == len(speeds) == N_BAG_SPEEDS
        np.testing.assert_allclose(real, want.real, rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(freq, want.imag / (2 * np.pi), rtol=1e-12, atol=1e-12)
    assert len(json.loads((bag / "eig.json").read_text())["speeds_mps"]) == N_SPEEDS
    (label,) = component_rows(rrd, "/vehicle/eigenvalues/model", "TextDocument:text")
    assert "/vehicle/eigenvalues" in label[1][0] and "lumped" in label[1][0]


def test_rerun_bag_without_eigenvalue_topic_uses_eig_json_roundtrip(converted, tmp_path):
    """A bag without /vehicle/eigenvalues: the series come from eig.json, labelled so."""
    from motoflex_ros.record.rerun_bag import convert_bag
    bag = tmp_path / "run2"
    make_bag(bag, eigenvalues=False)
    (bag / "eig.json").write_text((converted[0] / "eig.json").read_text())
    rrd, _ = convert_bag(bag)
    eig = json.loads((bag / "eig.json").read_text())
    got = scalar_values(rrd, "/vehicle/eigenvalues/weave/real_part")
    want = [np.nan if z is None else z[0] for z in eig["modes"]["weave"]]
    np.testing.assert_array_equal(got, want)
    assert entity_rows(rrd)["/vehicle/eigenvalues/all/real_part"] == N_SPEEDS
    (label,) = component_rows(rrd, "/vehicle/eigenvalues/model", "TextDocument:text")
    assert "eig.json" in label[1][0] and "rigid" in label[1][0]


def test_rerun_bag_joint_axes_roundtrip(converted):
    """Each revolute joint of the lumped motorcycle once, at its joint point along its axis."""
    bag, values, _ = converted
    rrd = bag / "run1.rrd"
    revolute = [j for j in lumped_motorcycle(values).joints if j.kind == "revolute"]
    drawn = sorted(p for p in entity_rows(rrd, static=True)
                   if p.startswith("/vehicle/joint_axes/") and not p.endswith("/joint"))
    assert drawn == sorted(f"/vehicle/joint_axes/{j.name}/{k}" for k, j in enumerate(revolute))
    for k, joint in enumerate(revolute):
        path = f"/vehicle/joint_axes/{joint.name}/{k}"
        (_, strips), = component_rows(rrd, path, "LineStrips3D:strips")
        (_, points), = component_rows(rrd, f"{path}/joint", "Points3D:positions")
        start, end = np.array(strips[0], float)
        axis = np.asarray(joint.axis, float) / np.linalg.norm(joint.axis)
        # rerun stores positions as float32
        np.testing.assert_allclose(points[0], joint.point, atol=1e-6)
        np.testing.assert_allclose((start + end) / 2, joint.point, atol=1e-6)
        np.testing.assert_allclose((end - start) / np.linalg.norm(end - start), axis, atol=1e-6)


def test_rerun_bag_identified_values_roundtrip(converted):
    bag, values, _ = converted
    for name, value in values.items():
        got = scalar_values(bag / "run1.rrd", f"/identification/frame/static/{name}")
        assert got == [pytest.approx(value, rel=1e-12)]


def test_rerun_not_a_bag_is_a_clear_error(tmp_path):
    result = run_motoflex(["rerun", tmp_path / "nope"])
    assert result.returncode == 2
    assert "not a bag" in result.stderr
    assert "Traceback" not in result.stderr


def test_rerun_motorcycle_ellipsoid_analytic():
    from motoflex_ros.record.rerun_motorcycle import ellipsoid_half_sizes
    # uniform solid ellipsoid, semi-axes a, b, c: I_x = m (b^2 + c^2) / 5, ...
    m, a, b, c = 12.0, 0.3, 0.2, 0.1
    moments = [m * (b**2 + c**2) / 5, m * (a**2 + c**2) / 5, m * (a**2 + b**2) / 5]
    np.testing.assert_allclose(ellipsoid_half_sizes(m, moments), [a, b, c], rtol=1e-12)


def test_rerun_road_test_without_bag_bodies(tmp_path):
    """No /vehicle/bodies in the bag: the steer-pulse road test comes from the engine."""
    from motoflex_ros.config import resolve_config
    from motoflex_ros.record.rerun_log import RunRecording
    from motoflex_ros.record.rerun_motorcycle import log_motorcycle
    from motoflex_ros.vehicle.animation import motorcycle_motion
    from motoflex_ros.vehicle.model import load_vehicle
    model = load_vehicle(resolve_config("vehicles", "touring"))
    with RunRecording(tmp_path / "m.rrd", "m") as run:
        samples = log_motorcycle(run.stream, motorcycle_motion(model))
    rows = entity_rows(tmp_path / "m.rrd")
    assert samples > 100
    for body in ("frame", "upper_fork", "front_wheel", "rear_wheel"):
        assert rows[f"/vehicle/road_test/{body}"] == samples
        assert rows[f"/vehicle/modes/wobble/{body}"] == MODE_FRAMES
    assert rows["/vehicle/road_test/joints/steer"] == samples
    assert "1 file verified without error." in verify_text(tmp_path / "m.rrd")


def _mode_rotations(rrd, entity):
    from rerun.chunk import RrdReader
    for chunk in RrdReader(rrd).stream().to_chunks():
        if chunk.entity_path == entity and not chunk.is_static:
            batch = chunk.to_record_batch()
            flat = batch.column(batch.schema.get_field_index("Transform3D:mat3x3")).to_pylist()
            # rerun stores Mat3x3 column-major
            return np.array([np.reshape(row[0], (3, 3)).T for row in flat])
    raise AssertionError(f"{entity} has no rotations")


def test_rerun_weave_animation_roundtrip(tmp_path):
    """The rear frame's logged attitude is the eigenvector's yaw and roll, frame by frame."""
    from scipy.spatial.transform import Rotation

    from motoflex_ros.config import resolve_config
    from motoflex_ros.record.rerun_log import RunRecording
    from motoflex_ros.record.rerun_motorcycle import log_motorcycle
    from motoflex_ros.vehicle.animation import mode_rows, motorcycle_motion
    from motoflex_ros.vehicle.linearize import linearize
    from motoflex_ros.vehicle.model import load_vehicle
    from motoflex_ros.vehicle.modes import modal_sweep
    model = load_vehicle(resolve_config("vehicles", "touring"))
    speed = 100 / 3.6
    lin = linearize(model)
    weave = modal_sweep(lin, np.array([speed])).modes["weave"][0]
    with RunRecording(tmp_path / "w.rrd", "w") as run:
        log_motorcycle(run.stream, motorcycle_motion(model, speed, modes={"weave": weave},
                                                     road=False))
    rows, lam = mode_rows(lin, speed, weave)
    assert lam == pytest.approx(weave, abs=1e-9)
    names = [c.name for c in lin.system.tree.coordinates]
    # base rotations: yaw about z, then roll about x, then pitch about y (intrinsic)
    euler = Rotation.from_matrix(_mode_rotations(tmp_path / "w.rrd",
                                                 "/vehicle/modes/weave/frame")).as_euler("ZXY")
    np.testing.assert_allclose(euler[:, 0], rows[:, names.index("yaw")], atol=1e-6)
    np.testing.assert_allclose(euler[:, 1], rows[:, names.index("roll")], atol=1e-6)
    assert np.abs(rows[:, names.index("roll")]).max() > 0.01


def test_rerun_modes_at_a_chosen_speed(tmp_path):
    """``--mode-speed-kmh``: weave and wobble animated at that speed, each on its own entity
    with its eigenvalue and exaggeration stated; a speed out of range is refused."""
    bag = tmp_path / "run"
    make_bag(bag)
    result = run_motoflex(["rerun", bag, "--mode-speed-kmh", "60"])
    assert result.returncode == 0, result.stderr
    rrd = next(bag.glob("*.rrd"))
    for mode in ("weave", "wobble"):
        (text,) = component_rows(rrd, f"/vehicle/modes/{mode}/description",
                                 "TextDocument:text")
        assert f"{mode} at 60 km/h" in text[1][0] and "largest angle is 0.15 rad" in text[1][0]
    bad = run_motoflex(["rerun", bag, "--mode-speed-kmh", "500"])
    assert bad.returncode == 2 and "--mode-speed-kmh" in bad.stderr
    assert "Traceback" not in bad.stderr


def test_road_test_bodies_take_their_names_from_tf():
    """The bag's /tf names the /vehicle/bodies poses (vehicle -> vehicle/<body>, same order);
    without /tf they are body0, body1, ..."""
    from types import SimpleNamespace as NS

    from motoflex_ros.record.rerun_bag_vehicle import body_names

    def tf(parent, child):
        return NS(header=NS(frame_id=parent), child_frame_id=child)
    message = NS(transforms=[tf("odom", "vehicle"), tf("vehicle", "vehicle/frame"),
                             tf("vehicle", "vehicle/upper_fork"), tf("world", "frame_clamp")])
    assert body_names({"/tf": [(None, message)]}, 2) == ["frame", "upper_fork"]
    assert body_names({"/tf": [(None, message)]}, 3) == ["body0", "body1", "body2"]
    assert body_names({}, 2) == ["body0", "body1"]
