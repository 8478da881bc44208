"""Convert a recorded run (rosbag2 MCAP directory) into a rerun recording bags/<run>/<run>.rrd.

Reads the bag with :mod:`motoflex_ros.record.mcap_bag` and decodes the CDR messages with the
rosbags type store (no rclpy needed), then logs with :mod:`.rerun_log` and
:mod:`.rerun_vehicle`. Topics (issue 8):

- /bench/<c>/load (geometry_msgs/WrenchStamped): load arrow and force series; with the
  shipped component model <c> also the beam model deformed by the quasi-static expansion of the
  recorded load, x = K^-1 f(t) on the clamped reduced model (exact for the quasi-static test,
  the static part of the shape for harmonic tests; the recording says so).
- /bench/<c>/pose (geometry_msgs/PoseStamped): loaded-end displacement series.
- /bench/<c>/markers/true and /measured (geometry_msgs/PoseArray): marker points over time.
- /identification/results (diagnostic_msgs/DiagnosticArray, one status per component and
  test, KeyValue values): scalars, and the static/torsion/bending axes from l and beta.
- /vehicle/joint_states (sensor_msgs/JointState), /vehicle/bodies (geometry_msgs/PoseArray),
  visualization_msgs/Marker joint axes: the road test and the identified axes.

Result files of the run folder are logged too: identification.json (or identify.json: the
static, torsion, bending and sweep axes, k_t and k_b) and eig.json (eigenvalues against speed,
weave and wobble).

Times are the header stamps (the rig's simulated time; the bag's log times are the recorder's
wall clock); ``sim_time`` is measured from the earliest stamp, which is 0 for a simulated run.
"""
import functools
import json
import re
import sys
from collections import defaultdict
from pathlib import Path

import numpy as np
import rerun as rr
from tqdm import tqdm

from motoflex_ros.errors import MotoflexError
from motoflex_ros.record import rerun_log as rl
from motoflex_ros.record import rerun_vehicle as rv
from motoflex_ros.record.mcap_bag import bag_info, read_messages
from motoflex_ros.record.rerun_blueprint import default_blueprint

__all__ = ["convert_bag", "rrd_path_of", "BENCH_TOPIC", "decode"]

BENCH_TOPIC = re.compile(r"^/bench/(?P<component>[^/]+)/(?P<what>load|pose|markers/true|"
                         r"markers/measured)$")
MAX_MARKER_FRAMES = 400
BENCH_SPACING_M = 1.0     # lateral spacing of the components on the bench [m]


@functools.cache
def _typestore():
    from rosbags.typesys import Stores, get_typestore
    return get_typestore(Stores.ROS2_JAZZY)


def decode(message):
    """The rosbags message object of a :class:`~.mcap_bag.BagMessage` (CDR)."""
    return _typestore().deserialize_cdr(message.data, message.type)


def rrd_path_of(bag_dir):
    """bags/<run>/<run>.rrd for the bag directory bags/<run>."""
    bag_dir = Path(bag_dir)
    return bag_dir / f"{bag_dir.name}.rrd"


def _stamp_ns(msg):
    """Header stamp [ns] (the rig's simulated time; 0 is a valid stamp), or None."""
    header = getattr(msg, "header", None)
    if header is None:
        return None
    return header.stamp.sec * 1_000_000_000 + header.stamp.nanosec


def _collect(bag_dir):
    """Stamped messages grouped by topic: {topic: [(t_ns, msg), ...]} in recording order.

    Messages without a header (/clock, phase strings) carry no simulated time and are left out.
    """
    grouped = defaultdict(list)
    for message in read_messages(bag_dir):
        msg = decode(message)
        stamp = _stamp_ns(msg)
        if stamp is not None:
            grouped[message.topic].append((stamp, msg))
    return grouped


def _times(samples, t0_ns):
    return np.array([(t - t0_ns) * 1e-9 for t, _ in samples])


def _vec(v):
    return [v.x, v.y, v.z]


def _quat(q):
    return [q.x, q.y, q.z, q.w]


@functools.cache
def _model(component):
    """(Component, ReducedComponent) of a shipped component name, or None."""
    try:
        from motoflex_ros.structures import load_component
        comp = load_component(component)
        return comp, comp.clamped_reduced()
    except (MotoflexError, OSError, KeyError, ValueError):
        return None


def _static_shapes(reduced, forces):
    """Quasi-static node translations (n_t, n_nodes, 3) [m] under end forces (n_t, 3) [N]."""
    unit = np.column_stack([np.linalg.solve(reduced.K, reduced.end_load_vector(np.eye(6)[i]))
                            for i in range(3)])
    reduced_coords = np.asarray(forces, float) @ unit.T
    return np.stack([reduced.node_displacements(x)[:, :3] for x in reduced_coords])


def _log_bench_load(rec, component, samples, pose_samples, t0, model, bench_offset):
    times = _times(samples, t0)
    forces = np.array([_vec(m.wrench.force) for _, m in samples])
    q0 = model[0].q0 if model else None
    if pose_samples:
        positions = np.array([_vec(m.pose.position) for _, m in pose_samples])
        ref = q0 if q0 is not None else positions[0]
        pose_times, displacement = _times(pose_samples, t0), positions - ref
    else:
        pose_times, displacement = times, np.full((len(times), 3), np.nan)
    load_xyz = q0 if q0 is not None else np.zeros(3)
    rl.log_load(rec, component, times, forces, load_xyz, displacement, pose_times)
    if model:
        comp, reduced = model
        rl.log_component_frame(rec, component, comp.origin, bench_offset)
        picks = rl.subsample_indices(len(times))
        shapes = _static_shapes(reduced, forces[picks])
        factor = rl.exaggeration_factor(comp.node_xyz, shapes)
        rl.log_structure(rec, component, comp.node_xyz, comp.elements, times[picks], shapes,
                         factor, comp.clamp_xyz, comp.q0)
        rec.log(f"/bench/{component}/structure/exaggeration", rr.TextDocument(
            f"Deformed shape of {component}: quasi-static expansion x = K^-1 f(t) of the "
            f"recorded load on the clamped reduced model, exaggerated x{factor:g}."),
            static=True)


def _log_markers(rec, component, kind, samples, t0):
    times = _times(samples, t0)
    for i in rl.subsample_indices(len(times), MAX_MARKER_FRAMES):
        rec.set_time(rl.TIMELINE, duration=float(times[i]))
        points = [_vec(p.position) for p in samples[i][1].poses]
        color = (40, 200, 40) if kind == "true" else (200, 40, 200)
        rec.log(f"/bench/{component}/markers/{kind}", rr.Points3D(points, colors=color,
                                                                  radii=0.006))


def _status_key(name, known):
    parts = [p for p in re.split(r"[/:\s]+", name) if p]
    component = next((p for p in parts if p in known), parts[-2] if len(parts) > 1 else "run")
    test = parts[-1] if parts and parts[-1] != component else "result"
    return component, test


def _number(text):
    try:
        return float(text)
    except (TypeError, ValueError):
        return None


def _log_identification(rec, samples, t0, known, draw_axes):
    for t_ns, msg in samples:
        for status in msg.status:
            component, test = _status_key(status.name, known)
            values = {kv.key: _number(kv.value) for kv in status.values}
            values = {k: v for k, v in values.items() if v is not None}
            rl.log_identification(rec, component, test, values, (t_ns - t0) * 1e-9)
            model = _model(component) if component in known and draw_axes else None
            if model and test in rl.AXIS_COLORS and {"l", "beta"} <= values.keys():
                rl.log_axis(rec, component, test, values["l"], values["beta"], model[0].q0)


def _log_vehicle(rec, grouped, t0):
    joints = grouped.get("/vehicle/joint_states", [])
    if joints:
        names = list(joints[0][1].name)
        rv.log_joint_series(rec, names, _times(joints, t0),
                            [list(m.position) for _, m in joints])
    bodies = grouped.get("/vehicle/bodies", [])
    if bodies:
        count = len(bodies[0][1].poses)
        names = [f"body{i}" for i in range(count)]
        rv.log_body_shapes(rec, "/vehicle/road_test",
                           [rv.BodyShape(n, "box", (0.15, 0.1, 0.1)) for n in names])
        rv.log_body_poses(rec, "/vehicle/road_test", names, _times(bodies, t0),
                          [[_vec(p.position) for p in m.poses] for _, m in bodies],
                          [[_quat(p.orientation) for p in m.poses] for _, m in bodies])


def _log_markers_msgs(rec, samples):
    for _, marker in samples:
        if len(marker.points) >= 2:
            a, b = np.array(_vec(marker.points[0])), np.array(_vec(marker.points[1]))
            name = f"{marker.ns or 'axis'}_{marker.id}"
            rv.log_joint_axis(rec, name, (a + b) / 2, b - a, np.linalg.norm(b - a) / 2)


def _read_json(folder, *names):
    for name in names:
        if (folder / name).is_file():
            return json.loads((folder / name).read_text(encoding="utf-8"))
    return None


def _log_identified_axes(rec, identify, sim_time_s, log_values):
    """Axes (static, torsion, bending, sweep) and (``log_values``) values of identify-format
    results."""
    for component, result in identify.items():
        model = _model(component)
        if not isinstance(result, dict) or model is None:
            continue
        q0 = model[0].q0
        for test in ("static", "torsion", "bending"):
            values = result.get(test, {})
            if {"l", "beta"} <= values.keys():
                rl.log_axis(rec, component, test, values["l"], values["beta"], q0)
                if log_values:
                    rl.log_identification(rec, component, test, values, sim_time_s)
        sweep = result.get("sweep") or []
        if sweep:
            rl.log_sweep_axes(rec, component, [s["f_hz"] for s in sweep],
                              [s["l"] for s in sweep], [s["beta"] for s in sweep], q0)
        split = {k: result[k] for k in ("k_t", "k_b") if k in result}
        rl.log_identification(rec, component, "decomposition", split, sim_time_s)


def _pairs(values):
    return np.array([complex(*z) if z is not None else complex(np.nan, np.nan) for z in values])


def _log_eig(rec, eig):
    rv.log_eigenvalues(rec, eig["speeds_mps"], _padded(eig["eigenvalues"]),
                       {m: _pairs(v) for m, v in eig.get("modes", {}).items()})


def _padded(eigenvalues):
    """(n_speeds, n_max) complex, NaN-padded (the count may differ between speeds)."""
    width = max(len(e) for e in eigenvalues)
    out = np.full((len(eigenvalues), width), np.nan, complex)
    for i, row in enumerate(eigenvalues):
        out[i, :len(row)] = [complex(re, im) for re, im in row]
    return out


def _log_run_files(rec, folder, identify, end_time_s, log_values):
    """The run folder's result files: identification (axes, sweep) and eig.json."""
    done = []
    if identify:
        _log_identified_axes(rec, identify, end_time_s, log_values)
        done.append("identification")
    eig = _read_json(folder, "eig.json")
    if eig:
        _log_eig(rec, eig)
        done.append("eig")
    return done


def _log_vehicle_model(rec, vehicle, identify, road_test):
    from motoflex_ros.record.rerun_motorcycle import log_motorcycle, vehicle_model
    model, description = vehicle_model(vehicle, identify)
    log_motorcycle(rec, model, road_test=road_test)
    rec.log("/vehicle/model", rr.TextDocument(f"Motorcycle: {description}."), static=True)
    return [f"vehicle model: {description}"]


def _bench_topics(grouped):
    """{component: {what: samples}} of the /bench/<c>/... topics."""
    bench = defaultdict(dict)
    for topic, samples in grouped.items():
        match = BENCH_TOPIC.match(topic)
        if match:
            bench[match["component"]][match["what"]] = samples
    return bench


def _log_bench_topics(rec, bench, t0):
    converted = []
    for k, (component, topics) in enumerate(sorted(bench.items())):
        if "load" in topics:
            _log_bench_load(rec, component, topics["load"], topics.get("pose"), t0,
                            _model(component), (0.0, BENCH_SPACING_M * k, 0.0))
        for kind in ("true", "measured"):
            if f"markers/{kind}" in topics:
                _log_markers(rec, component, kind, topics[f"markers/{kind}"], t0)
        converted += [f"/bench/{component}/{what}" for what in topics]
    return converted


def _log_vehicle_topics(rec, grouped, info, t0):
    _log_vehicle(rec, grouped, t0)
    marker_topics = [t.name for t in info.topics if t.type == "visualization_msgs/msg/Marker"]
    for topic in marker_topics:
        _log_markers_msgs(rec, grouped[topic])
    return [t for t in ("/vehicle/joint_states", "/vehicle/bodies") if t in grouped] + \
        marker_topics


def convert_bag(bag_dir, rrd_path=None, vehicle="touring", progress=False):
    """Write the rerun recording of a recorded run; returns (rrd path, what was converted).

    ``vehicle`` (a shipped vehicle name, or None to skip) adds the motorcycle from the vehicle
    engine: bodies, joint axes, weave and wobble animated, and the steer-pulse road test when
    the bag has none. ``progress`` shows a tqdm bar (stderr) over the steps. Raises
    :class:`~.mcap_bag.BagError` when ``bag_dir`` is not a bag.
    """
    bag_dir = Path(bag_dir)
    info = bag_info(bag_dir)
    bar = tqdm(total=5, desc="rerun", unit="step", disable=not progress, file=sys.stderr)
    bar.set_postfix_str(f"reading {info.message_count} messages")
    grouped = _collect(bag_dir)
    t0 = min((t for samples in grouped.values() for t, _ in samples), default=0)
    bench = _bench_topics(grouped)
    identify = _read_json(bag_dir, "identification.json", "identify.json")
    with bar:
        with rl.RunRecording(rrd_path or rrd_path_of(bag_dir), bag_dir.name,
                             default_blueprint(sorted(bench))) as run:
            converted = _log_all(run.stream, bar, grouped, bench, t0, info, identify, vehicle)
            _step(bar, "writing")
        bar.update(1)
    return run.path, sorted(converted)


def _log_all(rec, bar, grouped, bench, t0, info, identify, vehicle):
    """Log bench, identification, vehicle topics, the run's result files and the model."""
    _step(bar, "bench")
    converted = _log_bench_topics(rec, bench, t0)
    _step(bar, "identification")
    if "/identification/results" in grouped:
        _log_identification(rec, grouped["/identification/results"], t0, set(bench),
                            draw_axes=identify is None)
        converted.append("/identification/results")
    converted += _log_vehicle_topics(rec, grouped, info, t0)
    converted += _log_run_files(rec, info.path, identify, info.duration_ns * 1e-9,
                                log_values="/identification/results" not in grouped)
    _step(bar, "vehicle model")
    if vehicle:
        converted += _log_vehicle_model(rec, vehicle, identify,
                                        road_test="/vehicle/bodies" not in grouped)
    return converted


def _step(bar, name):
    bar.update(1)
    bar.set_postfix_str(name)
