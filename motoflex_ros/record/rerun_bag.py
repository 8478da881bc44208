"""Convert a recorded run (rosbag2 MCAP directory) into a rerun recording bags/<run>/<run>.rrd.

Reads the bag with :mod:`motoflex_ros.record.mcap_bag` and decodes the CDR messages with the
rosbags type store (no rclpy needed), then logs with :mod:`.rerun_log` and
:mod:`.rerun_vehicle`. Topics (issue 8):

- /bench/<c>/load (geometry_msgs/WrenchStamped) with /bench/<c>/phase (std_msgs/String): load
  arrow and force series; with the shipped component model <c> also the beam model deformed by
  the time response of the clamped reduced model to the recorded load history, the component
  simulator's own (:mod:`motoflex_ros.bench.replayed_loads`).
- /bench/<c>/pose (geometry_msgs/PoseStamped): loaded-end displacement series.
- /bench/<c>/markers/true and /measured (geometry_msgs/PoseArray): marker points over time.
- /identification/results (diagnostic_msgs/DiagnosticArray, one status per component and
  test, KeyValue values): scalars, and the static/torsion/bending axes from l and beta.
- /vehicle/eigenvalues (diagnostic_msgs/DiagnosticArray, one status 'vehicle/<mode>' per
  tracked mode with JSON lists speeds_kmh, real [1/s], frequency_hz): eigenvalues against
  speed of the lumped motorcycle the vehicle_simulator built from the run's identified values.
- /vehicle/joint_states (sensor_msgs/JointState), /vehicle/bodies (geometry_msgs/PoseArray),
  visualization_msgs/Marker joint axes (an arrow from the joint point along the axis): the road
  test and the identified axes, one entity /vehicle/joint_axes/<ns>/<id> per marker.

Result files of the run folder are logged too: identification.json (or identify.json: the
static, torsion, bending and sweep axes, k_t and k_b) and, only when the bag has no
/vehicle/eigenvalues, eig.json (eigenvalues against speed of ``motoflex eig``, which names its
model). /vehicle/eigenvalues/model states which one was logged.

Times are the header stamps (the rig's simulated time; the bag's log times are the recorder's
wall clock); ``sim_time`` is measured from the earliest stamp, which is 0 for a simulated run.
"""
import functools
import re
from collections import defaultdict
from pathlib import Path

import numpy as np
import rerun as rr

from motoflex_ros.bench.replayed_loads import recorded_samples, replayed_displacements
from motoflex_ros.files import read_json
from motoflex_ros.formats.component_file import shipped_model
from motoflex_ros.frames import BENCH_SPACING_M
from motoflex_ros.progress import progress_bar
from motoflex_ros.record import rerun_log as rl
from motoflex_ros.record.mcap_bag import BagError, bag_info, read_messages
from motoflex_ros.record.rerun_bag_vehicle import (
    EIG_TOPIC,
    log_eig_file,
    log_vehicle_model,
    log_vehicle_topics,
    times_s,
    vec,
)
from motoflex_ros.record.rerun_blueprint import default_blueprint
from motoflex_ros.units import NS_PER_S

__all__ = ["convert_bag", "rrd_path_of", "run_identification", "BENCH_TOPIC", "decode",
           "COMPONENTS_FILE"]

COMPONENTS_FILE = "component_files.json"
"""A run folder's {component name: YAML file} of the components that came from a file (a
``component: mesh`` file, a beam YAML of one's own): what draws them on the bench."""

BENCH_TOPIC = re.compile(r"^/bench/(?P<component>[^/]+)/(?P<what>load|phase|pose|markers/true|"
                         r"markers/measured)$")
MAX_MARKER_FRAMES = 400


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
    return header.stamp.sec * NS_PER_S + header.stamp.nanosec


def _collect(bag_dir):
    """Messages grouped by topic: {topic: [(t_ns, msg), ...]} in recording order.

    Messages without a header carry no simulated time: the bench's phase labels (they pair
    with the loads by order) and tf (it names the bodies) are kept with t_ns None, others
    (/clock) are left out undecoded.
    """
    grouped = defaultdict(list)
    for message in read_messages(bag_dir):
        unstamped = (message.type == "std_msgs/msg/String" and message.topic.endswith("/phase")
                     or message.type == "tf2_msgs/msg/TFMessage")
        if message.type == "rosgraph_msgs/msg/Clock":
            continue
        msg = decode(message)
        stamp = _stamp_ns(msg)
        if stamp is not None or unstamped:
            grouped[message.topic].append((stamp, msg))
    return grouped


_SOURCES = {}
"""{component name: YAML file} of the bag being converted (its component_files.json: the
campaign writes it when a component came from a file)."""


def _model(component):
    """(Component, ReducedComponent) of a component of the bag (a shipped name, or the file the
    bag's component_files.json names), or None (:func:`motoflex_ros.formats.component_file.
    shipped_model`)."""
    return shipped_model(_SOURCES.get(component, component))


def _log_bench_load(rec, component, topics, t0, model, bench_offset):
    samples, pose_samples = topics["load"], topics.get("pose")
    times = times_s(samples, t0)
    forces = np.array([vec(m.wrench.force) for _, m in samples])
    q0 = model[0].q0 if model else None
    if pose_samples:
        positions = np.array([vec(m.pose.position) for _, m in pose_samples])
        ref = q0 if q0 is not None else positions[0]
        pose_times, displacement = times_s(pose_samples, t0), positions - ref
    else:
        pose_times, displacement = times, np.full((len(times), 3), np.nan)
    load_xyz = q0 if q0 is not None else np.zeros(3)
    rl.log_load(rec, component, times, forces, load_xyz, displacement, pose_times)
    if model:
        rl.log_component_frame(rec, component, model[0].origin, bench_offset)
        phases = [m.data for _, m in topics.get("phase", [])]
        torques = [vec(m.wrench.torque) for _, m in samples]
        _log_replayed_structure(rec, component, model, times, recorded_samples(
            phases, [(t, (*f, *m)) for (t, _), f, m in zip(samples, forces, torques)]))


def _log_replayed_structure(rec, component, model, times, loads):
    """The beam deformed by the clamped reduced model's time response to the recorded loads."""
    comp, reduced = model
    picks = rl.subsample_indices(len(times))
    shapes = replayed_displacements(reduced, loads.samples, picks)
    factor = rl.exaggeration_factor(comp.node_xyz, shapes)
    source = ("the test phases and loads recorded on /bench/{c}/phase and /bench/{c}/load "
              "(each test from rest, a decay test from equilibrium under its preload)"
              if loads.labelled else "the loads recorded on /bench/{c}/load (no phase labels: "
              "one test from rest, first-order hold between the stamps)").format(c=component)
    rl.log_structure(rec, component, comp.node_xyz, comp.elements, times[picks], shapes,
                     factor, comp.clamp_xyz, comp.q0, source=(
                         "time response of the clamped reduced model (the component "
                         f"simulator's exact discretisation) to {source}"))


def _log_markers(rec, component, kind, samples, t0):
    times = times_s(samples, t0)
    for i in rl.subsample_indices(len(times), MAX_MARKER_FRAMES):
        rec.set_time(rl.TIMELINE, duration=float(times[i]))
        points = [vec(p.position) for p in samples[i][1].poses]
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
    tables = defaultdict(dict)
    for t_ns, msg in samples:
        for status in msg.status:
            component, test = _status_key(status.name, known)
            values = {kv.key: _number(kv.value) for kv in status.values}
            values = {k: v for k, v in values.items() if v is not None}
            tables[component][test] = values
            rl.log_identification(rec, component, test, values, (t_ns - t0) * 1e-9)
            model = _model(component) if component in known and draw_axes else None
            if model and test in rl.AXIS_COLORS and {"l", "beta"} <= values.keys():
                rl.log_axis(rec, component, test, values["l"], values["beta"], model[0].q0)
    for component, tests in tables.items():
        split = {k: v for values in tests.values() for k, v in values.items()
                 if k in ("k_t", "k_b")}
        rl.log_identification_table(rec, component, {
            t: v for t, v in tests.items() if t in ("static", "torsion", "bending")}, split)


def _read_json(folder, *names):
    for name in names:
        if (folder / name).is_file():
            try:
                return read_json(folder / name)
            except ValueError as exc:
                raise BagError(f"{folder / name}: not a readable JSON file ({exc})") from None
    return None


def _log_identified_axes(rec, identify, sim_time_s, log_values):
    """Axes (static, torsion, bending, the principal hinges, sweep) and (``log_values``)
    values of identify-format results."""
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
        principal = result.get("principal") or {}
        hinges = principal.get("hinges") or [] if principal.get("identified") else []
        for i, hinge in enumerate(hinges):
            rl.log_axis(rec, component, f"principal_{i + 1}", hinge["l"], hinge["beta"], q0)
            if log_values:
                rl.log_identification(rec, component, f"principal_{i + 1}", hinge, sim_time_s)
        sweep = result.get("sweep") or []
        if sweep:
            rl.log_sweep_axes(rec, component, [s["f_hz"] for s in sweep],
                              [s["l"] for s in sweep], [s["beta"] for s in sweep], q0)
        split = {k: result[k] for k in ("k_t", "k_b") if k in result}
        rl.log_identification(rec, component, "decomposition", split, sim_time_s)
        rl.log_identification_table(rec, component, {
            t: result[t] for t in ("static", "torsion", "bending") if isinstance(
                result.get(t), dict)}, split)


def _log_run_files(rec, folder, identify, end_time_s, log_values, with_eig):
    """The run folder's result files: identification (axes, sweep) and (``with_eig``)
    eig.json."""
    done = []
    if identify:
        _log_identified_axes(rec, identify, end_time_s, log_values)
        done.append("identification")
    eig = _read_json(folder, "eig.json") if with_eig else None
    if eig:
        log_eig_file(rec, eig)
        done.append("eig")
    return done


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
            _log_bench_load(rec, component, topics, t0, _model(component),
                            (0.0, BENCH_SPACING_M * k, 0.0))
        for kind in ("true", "measured"):
            if f"markers/{kind}" in topics:
                _log_markers(rec, component, kind, topics[f"markers/{kind}"], t0)
        converted += [f"/bench/{component}/{what}" for what in topics]
    return converted


def run_identification(bag_dir):
    """The run folder's identification results (identification.json or identify.json), or
    None."""
    return _read_json(Path(bag_dir), "identification.json", "identify.json")


def convert_bag(bag_dir, rrd_path=None, motorcycle=None, progress=False):
    """Write the rerun recording of a recorded run; returns (rrd path, what was converted).

    ``motorcycle`` (None to skip): (MotorcycleMotion, description) of the motorcycle to draw
    beside the bag's topics (bodies, joint axes, weave and wobble animated, and the steer-pulse
    road test when the bag has none), computed by the caller. ``progress`` shows a tqdm bar
    (stderr) over the steps. Raises :class:`~.mcap_bag.BagError` when ``bag_dir`` is not a bag.
    """
    bag_dir = Path(bag_dir)
    info = bag_info(bag_dir)
    bar = progress_bar(total=5, desc="rerun", unit="step", enabled=progress)
    bar.set_postfix_str(f"reading {info.message_count} messages")
    grouped = _collect(bag_dir)
    t0 = min((t for samples in grouped.values() for t, _ in samples if t is not None),
             default=0)
    bench = _bench_topics(grouped)
    identify = run_identification(bag_dir)
    _SOURCES.clear()
    _SOURCES.update(_read_json(bag_dir, COMPONENTS_FILE) or {})
    with bar:
        with rl.RunRecording(rrd_path or rrd_path_of(bag_dir), bag_dir.name,
                             default_blueprint) as run:
            converted = _log_all(run.stream, bar, grouped, bench, t0, info, identify,
                                 motorcycle)
            _step(bar, "writing")
        bar.update(1)
    return run.path, sorted(converted)


def _log_all(rec, bar, grouped, bench, t0, info, identify, motorcycle):
    """Log bench, identification, vehicle topics, the run's result files and the model."""
    _step(bar, "bench")
    converted = _log_bench_topics(rec, bench, t0)
    _step(bar, "identification")
    if "/identification/results" in grouped:
        _log_identification(rec, grouped["/identification/results"], t0, set(bench),
                            draw_axes=identify is None)
        converted.append("/identification/results")
    model = motorcycle[0].model if motorcycle is not None else None
    vehicle_topics, bag_axes = log_vehicle_topics(rec, grouped, info, t0, model)
    converted += vehicle_topics
    converted += _log_run_files(rec, info.path, identify, info.duration_ns * 1e-9,
                                log_values="/identification/results" not in grouped,
                                with_eig=EIG_TOPIC not in vehicle_topics)
    _step(bar, "vehicle model")
    if motorcycle is not None:
        span = max((t for samples in grouped.values() for t, _ in samples if t is not None),
                   default=t0) - t0
        converted += log_vehicle_model(rec, motorcycle,
                                        road_test="/vehicle/bodies" not in grouped,
                                        joint_axes=bag_axes == 0, sim_span_s=span * 1e-9)
    return converted


def _step(bar, name):
    bar.update(1)
    bar.set_postfix_str(name)
