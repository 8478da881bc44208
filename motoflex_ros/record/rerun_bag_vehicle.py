"""The vehicle part of a recorded run in its rerun recording: road test, joint axes, eigenvalues.

Used by :mod:`.rerun_bag`. Decodes (rosbags message objects):

- /vehicle/joint_states (sensor_msgs/JointState), /vehicle/bodies (geometry_msgs/PoseArray):
  the road test over ``sim_time``;
- visualization_msgs/Marker joint axes: an ARROW from the joint point along the axis (as
  :func:`motoflex_ros.nodes.conversions.axis_marker` draws it), one entity
  /vehicle/joint_axes/<ns>/<id> per marker left after the recorded ADD/DELETE actions;
- /vehicle/eigenvalues (diagnostic_msgs/DiagnosticArray of the vehicle_simulator node): the
  tracked modes against speed, preferred over the run folder's eig.json (``motoflex eig``,
  which names its model); /vehicle/eigenvalues/model says which was logged.
"""
import json
from dataclasses import replace

import numpy as np
import rerun as rr
from scipy.spatial.transform import Rotation

from motoflex_ros.frames import VEHICLE_FRAME
from motoflex_ros.record import rerun_vehicle as rv
from motoflex_ros.record.rerun_motorcycle import log_motorcycle, posed_body_geometry
from motoflex_ros.units import kmh_to_ms
from motoflex_ros.vehicle.variants import variant_label

__all__ = ["EIG_TOPIC", "MARKER_TYPE", "times_s", "vec", "quat", "marker_axis",
           "bag_eigenvalues", "log_vehicle_topics", "log_eig_file", "log_vehicle_model"]

EIG_TOPIC = "/vehicle/eigenvalues"
MARKER_TYPE = "visualization_msgs/msg/Marker"
ARROW, DELETE, DELETE_ALL = 0, 2, 3   # visualization_msgs/Marker type and actions


def times_s(samples, t0_ns):
    """Header stamps [ns] of (t_ns, msg) samples as seconds [s] from ``t0_ns``."""
    return np.array([(t - t0_ns) * 1e-9 for t, _ in samples])


def vec(v):
    """[x, y, z] of a Vector3 or Point."""
    return [v.x, v.y, v.z]


def quat(q):
    """[x, y, z, w] of a Quaternion."""
    return [q.x, q.y, q.z, q.w]


def _log_road_test(rec, grouped, t0, model=None):
    """Joint coordinates and body poses of the bag's road test over ``sim_time``; the bodies
    drawn with the geometry of ``model`` (the motorcycle the recording draws) where it has
    them, else as small boxes."""
    joints = grouped.get("/vehicle/joint_states", [])
    if joints:
        names = list(joints[0][1].name)
        rv.log_joint_series(rec, names, times_s(joints, t0),
                            [list(m.position) for _, m in joints])
    bodies = grouped.get("/vehicle/bodies", [])
    if bodies:
        names = body_names(grouped, len(bodies[0][1].poses))
        geometry = {} if model is None else posed_body_geometry(model, names)
        for name in geometry:
            for k, part in enumerate(geometry[name]):
                rec.log(f"/vehicle/road_test/{name}/shape/{k}", part, static=True)
        rv.log_body_shapes(rec, "/vehicle/road_test",
                           [rv.BodyShape(n, "box", (0.15, 0.1, 0.1)) for n in names
                            if n not in geometry])
        rv.log_body_poses(rec, "/vehicle/road_test", names, times_s(bodies, t0),
                          [[vec(p.position) for p in m.poses] for _, m in bodies],
                          [[quat(p.orientation) for p in m.poses] for _, m in bodies])


def body_names(grouped, count):
    """Names of the ``count`` poses of /vehicle/bodies: the child frames vehicle/<body> the
    bag's /tf gives them (the same order: :func:`motoflex_ros.frames.vehicle_transforms`), or
    body0, body1, ... for a bag without them."""
    prefix = VEHICLE_FRAME + "/"
    for _, message in grouped.get("/tf", []):
        children = [t.child_frame_id for t in message.transforms
                    if t.header.frame_id == VEHICLE_FRAME and t.child_frame_id.startswith(prefix)]
        if len(children) == count:
            return [c[len(prefix):] for c in children]
    return [f"body{i}" for i in range(count)]


def marker_axis(marker):
    """(joint point [m], axis direction) of a joint-axis ARROW marker, or None.

    With points, the arrow starts at the joint and points along the axis (as
    :func:`motoflex_ros.nodes.conversions.axis_marker` draws it); without, it starts at the
    pose's position along the pose's x axis (the Marker convention).
    """
    if marker.type != ARROW:
        return None
    if len(marker.points) >= 2:
        start = np.array(vec(marker.points[0]))
        direction = np.array(vec(marker.points[1])) - start
    else:
        start = np.array(vec(marker.pose.position))
        direction = Rotation.from_quat(quat(marker.pose.orientation)).apply([1.0, 0.0, 0.0])
    return (start, direction) if np.linalg.norm(direction) > 0 else None


def _current_markers(samples):
    """{(ns, id): marker} left after the recorded ADD, DELETE and DELETEALL actions."""
    current = {}
    for _, marker in samples:
        if marker.action == DELETE_ALL:
            current.clear()
        elif marker.action == DELETE:
            current.pop((marker.ns, marker.id), None)
        else:
            current[(marker.ns, marker.id)] = marker
    return current


def _log_markers_msgs(rec, samples):
    """Joint axes of the bag's markers, one entity /vehicle/joint_axes/<ns>/<id> each."""
    logged = 0
    for (ns, marker_id), marker in sorted(_current_markers(samples).items()):
        axis = marker_axis(marker)
        if axis is not None:
            rv.log_joint_axis(rec, f"{ns or 'axis'}/{marker_id}", *axis)
            logged += 1
    return logged


def _pairs(values):
    return np.array([complex(*z) if z is not None else complex(np.nan, np.nan) for z in values])


def log_eig_file(rec, eig):
    """Eigenvalues against speed of a ``motoflex eig --json`` result (eig.json), labelled."""
    rv.log_eigenvalues(rec, eig["speeds_mps"], _padded(eig["eigenvalues"]),
                       {m: _pairs(v) for m, v in eig.get("modes", {}).items()})
    model = (variant_label(eig["variant"], eig["components"]) if "variant" in eig
             else "model not recorded")
    rec.log("/vehicle/eigenvalues/model", rr.TextDocument(
        f"Eigenvalues against speed from eig.json (motoflex eig: {model}); the bag has no "
        f"{EIG_TOPIC}."), static=True)


def _padded(eigenvalues):
    """(n_speeds, n_max) complex, NaN-padded (the count may differ between speeds)."""
    width = max(len(e) for e in eigenvalues)
    out = np.full((len(eigenvalues), width), np.nan, complex)
    for i, row in enumerate(eigenvalues):
        out[i, :len(row)] = [complex(re, im) for re, im in row]
    return out


def bag_eigenvalues(msg):
    """Speeds [m/s] and {mode: eigenvalue per speed, complex [1/s]} of /vehicle/eigenvalues.

    ``msg`` is the diagnostic_msgs/DiagnosticArray of the vehicle_simulator node
    (:func:`motoflex_ros.nodes.result_messages.mode_statuses`): one status 'vehicle/<mode>' with
    JSON lists speeds_kmh, real [1/s] and frequency_hz [Hz] (null where the mode is not
    found: NaN here); lambda = real + 2 pi i frequency_hz. ValueError when the modes' speeds
    differ.
    """
    speeds_kmh, modes = None, {}
    for status in msg.status:
        values = {kv.key: json.loads(kv.value) for kv in status.values}
        if not {"speeds_kmh", "real", "frequency_hz"} <= values.keys():
            continue
        if speeds_kmh is not None and values["speeds_kmh"] != speeds_kmh:
            raise ValueError(f"{status.name}: speeds differ from the other modes'")
        speeds_kmh = values["speeds_kmh"]
        real, freq = (np.array(values[k], float) for k in ("real", "frequency_hz"))
        modes[status.name.rsplit("/", 1)[-1]] = real + 2j * np.pi * freq
    return kmh_to_ms(np.array(speeds_kmh or [], float)), modes


def _log_bag_eigenvalues(rec, samples):
    """The last /vehicle/eigenvalues message: tracked modes against speed, labelled."""
    speeds, modes = bag_eigenvalues(samples[-1][1])
    if not modes:
        return False
    text = (f"Eigenvalues against speed ({', '.join(modes)}) from the bag's {EIG_TOPIC}: the "
            "lumped motorcycle the vehicle_simulator node built from this run's identified "
            "stiffness.")
    try:
        rv.log_eigenvalues(rec, speeds, None, modes)
    except ValueError as exc:       # speeds closer than the speed_kmh timeline resolves
        text += f" Not plotted: {exc}."
    rec.log("/vehicle/eigenvalues/model", rr.TextDocument(text), static=True)
    return True


def log_vehicle_topics(rec, grouped, info, t0, model=None):
    """Road test (drawn with ``model``'s geometry), joint-axis markers and eigenvalues of the
    bag; returns (topics, axes drawn)."""
    _log_road_test(rec, grouped, t0, model)
    converted = [t for t in ("/vehicle/joint_states", "/vehicle/bodies") if t in grouped]
    axes = 0
    for topic in (t.name for t in info.topics if t.type == MARKER_TYPE):
        axes += _log_markers_msgs(rec, grouped[topic])
        converted.append(topic)
    if EIG_TOPIC in grouped and _log_bag_eigenvalues(rec, grouped[EIG_TOPIC]):
        converted.append(EIG_TOPIC)
    return converted, axes


def log_vehicle_model(rec, motorcycle, road_test, joint_axes, sim_span_s=None):
    """The motorcycle from the vehicle engine: ``motorcycle`` = (MotorcycleMotion,
    description) computed by the caller (:mod:`motoflex_ros.vehicle.animation`); without the
    road test or the joint axes when the bag has them."""

    motion, description = motorcycle
    log_motorcycle(rec, motion if road_test else replace(motion, road=None),
                   joint_axes=joint_axes, sim_span_s=sim_span_s)
    rec.log("/vehicle/model", rr.TextDocument(f"Motorcycle: {description}."), static=True)
    return [f"vehicle model: {description}"]
