"""Conversions between the core's numbers (SI, numpy) and ROS 2 messages. Nothing else here.

Times: integer nanoseconds of simulated time <-> builtin_interfaces/Time.

The per-sample messages of the bench (phase, load, markers, pose) also have fast paths that
write and read the serialized form (little-endian CDR, as rclpy's serializer writes it, padding
zeroed) without Python message objects: the graph handles about 11,500 samples, and building
and converting message objects cost tens of microseconds per message and node.
"""
import json
import math
import struct

import numpy as np
from builtin_interfaces.msg import Time
from diagnostic_msgs.msg import DiagnosticStatus, KeyValue
from geometry_msgs.msg import Pose, PoseArray, PoseStamped, WrenchStamped
from rclpy.serialization import deserialize_message
from rosgraph_msgs.msg import Clock
from std_msgs.msg import String

from motoflex_ros.bench.actuator import LATERAL_WRENCH, LoadSample, wrench_amplitude

__all__ = ["time_msg", "time_ns", "clock_msg", "seconds_to_ns", "clock_ns_from_cdr",
           "wrench_msg", "phase_msg", "sample_from_phase", "points_msg", "points_from_msg",
           "pose_msg", "identification_statuses", "results_from_statuses", "quaternion_xyzw",
           "mode_statuses", "joint_state_msg", "poses_msg", "axis_marker", "points_cdr",
           "points_from_cdr", "wrench_cdr", "wrench_from_cdr", "wrench_vector_from_cdr",
           "phase_cdr", "phase_text",
           "pose_cdr", "is_end_marker", "transform_msg", "structure_markers", "qos_dict",
           "series_msg", "IDENTIFIED_MODELS", "IDENTIFIED_UNITS", "identified_series",
           "mode_series"]

NS_PER_S = 1_000_000_000


def seconds_to_ns(seconds):
    """Simulated time [s] -> integer nanoseconds, rounded to the nearest nanosecond."""
    return int(round(seconds * NS_PER_S))


def time_msg(ns):
    """builtin_interfaces/Time of ``ns`` nanoseconds (ns >= 0)."""
    sec, nanosec = divmod(int(ns), NS_PER_S)
    return Time(sec=sec, nanosec=nanosec)


def time_ns(stamp):
    """Integer nanoseconds of a builtin_interfaces/Time."""
    return stamp.sec * NS_PER_S + stamp.nanosec


def clock_msg(ns):
    """rosgraph_msgs/Clock at ``ns`` nanoseconds of simulated time."""
    return Clock(clock=time_msg(ns))


def clock_ns_from_cdr(data):
    """Simulated time [ns] of a serialized rosgraph_msgs/Clock (fast path: little-endian)."""
    if len(data) >= 12 and data[1] == 1:
        sec, nanosec = struct.unpack_from("<iI", data, 4)
        return sec * NS_PER_S + nanosec
    return time_ns(deserialize_message(data, Clock).clock)


# --- bench: loads, phases, markers, poses -------------------------------------------------

def _wrench_values(load):
    """(F_x, F_y, F_z, M_x, M_y, M_z) of a lateral force F_y [N] (a number) or a wrench (6,)."""
    if np.ndim(load) == 0:
        return (0.0, float(load), 0.0, 0.0, 0.0, 0.0)
    return tuple(float(v) for v in load)


def wrench_msg(ns, frame_id, load):
    """geometry_msgs/WrenchStamped at the loaded end: a lateral force F_y [N] (a number) or a
    wrench (F_x, F_y, F_z, M_x, M_y, M_z) [N, N m] (a moment test's torque)."""
    msg = WrenchStamped()
    msg.header.stamp = time_msg(ns)
    msg.header.frame_id = frame_id
    values = _wrench_values(load)
    msg.wrench.force.x, msg.wrench.force.y, msg.wrench.force.z = values[:3]
    msg.wrench.torque.x, msg.wrench.torque.y, msg.wrench.torque.z = values[3:]
    return msg


def phase_msg(sample=None, end_ns=None):
    """std_msgs/String (JSON) with a load sample's labels (``LoadSample.to_dict``: exact
    floats), or, with ``end_ns``, the end of a component's campaign.
    """
    data = {"end_ns": int(end_ns)} if sample is None else sample.to_dict()
    return String(data=json.dumps(data))


def sample_from_phase(msg, load):
    """(LoadSample, None) from a phase message (std_msgs/String, or its CDR bytes) and its
    load: F_y [N] (a number) or the wrench (6,) [N, N m], whose amplitude along the test's unit
    wrench (the label's, default F_y) is the sample's force; (None, end_ns) for the end marker.
    """
    data = json.loads(phase_text(msg))
    if "end_ns" in data:
        return None, data["end_ns"]
    if np.ndim(load) == 0:
        data["force"] = float(load)
    else:
        data["force"] = wrench_amplitude(data.get("wrench", LATERAL_WRENCH), load)
    return LoadSample.from_dict(data), None


def points_msg(ns, frame_id, points):
    """geometry_msgs/PoseArray of points (n, 3) [m] (identity orientations)."""
    msg = PoseArray()
    msg.header.stamp = time_msg(ns)
    msg.header.frame_id = frame_id
    for x, y, z in np.asarray(points, float).reshape(-1, 3):
        pose = Pose()
        pose.position.x, pose.position.y, pose.position.z = float(x), float(y), float(z)
        pose.orientation.w = 1.0
        msg.poses.append(pose)
    return msg


def points_from_msg(msg):
    """(n, 3) array [m] of the positions in a PoseArray."""
    return np.array([(p.position.x, p.position.y, p.position.z) for p in msg.poses],
                    float).reshape(-1, 3)


def pose_msg(ns, frame_id, position, rotation):
    """geometry_msgs/PoseStamped of a position [m] and rotation matrix."""
    msg = PoseStamped()
    msg.header.stamp = time_msg(ns)
    msg.header.frame_id = frame_id
    msg.pose.position.x, msg.pose.position.y, msg.pose.position.z = map(float, position)
    x, y, z, w = quaternion_xyzw(rotation)
    msg.pose.orientation.x, msg.pose.orientation.y = float(x), float(y)
    msg.pose.orientation.z, msg.pose.orientation.w = float(z), float(w)
    return msg


def quaternion_xyzw(rotation):
    """Unit quaternion (x, y, z, w) of a rotation matrix (Shepperd's method, w >= 0 branch
    first; exact for the small rotations of the bench).
    """
    r = np.asarray(rotation, float)
    trace = r[0, 0] + r[1, 1] + r[2, 2]
    if trace > 0.0:
        s = 2.0 * math.sqrt(1.0 + trace)
        return ((r[2, 1] - r[1, 2]) / s, (r[0, 2] - r[2, 0]) / s, (r[1, 0] - r[0, 1]) / s,
                0.25 * s)
    i = int(np.argmax(np.diag(r)))
    j, k = (i + 1) % 3, (i + 2) % 3
    s = 2.0 * math.sqrt(1.0 + r[i, i] - r[j, j] - r[k, k])
    q = [0.0, 0.0, 0.0, (r[k, j] - r[j, k]) / s]
    q[i], q[j], q[k] = 0.25 * s, (r[j, i] + r[i, j]) / s, (r[k, i] + r[i, k]) / s
    return tuple(q)


# --- identification results ---------------------------------------------------------------

def _key_values(values):
    out = []
    for key, value in values.items():
        if isinstance(value, dict):
            out += [KeyValue(key=f"{key}.{k}", value=kv.value)
                    for kv in _key_values(value) for k in [kv.key]]
        else:
            out.append(KeyValue(key=str(key), value=repr(_plain(value))))
    return out


def _plain(value):
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, (list, tuple, np.ndarray)):
        return [_plain(v) for v in value]
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items()}
    return value


def identification_statuses(component, result_dict):
    """diagnostic_msgs/DiagnosticStatus list, one per test/model of a component's result dict
    (``ComponentIdentification.to_dict``): name '<component>/<test>', values as KeyValue with
    dotted keys and ``repr`` values (exact floats; None for NaN, an undefined value). The
    split status is WARN with the reason when eq. (12) gave no identifiable k_t, k_b, the
    principal status when the principal hinges are not identified.
    """
    statuses, top = [], {}
    for test, values in result_dict.items():
        if isinstance(values, dict) and test != "ci":
            statuses.append(_status(f"{component}/{test}", values))
        elif isinstance(values, list):
            statuses += [_status(f"{component}/{test}_{i:02d}", v) for i, v in enumerate(values)]
        else:
            top[test] = values
    split = _status(f"{component}/split", top)
    if top.get("split_identifiable") is False:  # eq. (12) gave no usable k_t, k_b
        split.level, split.message = DiagnosticStatus.WARN, str(top.get("split_problem"))
    statuses.insert(0, split)
    principal = result_dict.get("principal")
    if isinstance(principal, dict) and not principal.get("identified"):  # with the reason
        status = next(s for s in statuses if s.name == f"{component}/principal")
        status.level, status.message = DiagnosticStatus.WARN, str(principal.get("problem"))
    return statuses


def _status(name, values):
    return DiagnosticStatus(level=DiagnosticStatus.OK, name=name, message="identified",
                            hardware_id="motoflex_ros", values=_key_values(values))


def results_from_statuses(statuses):
    """Identify-format dict {component: {...}} rebuilt from DiagnosticStatus messages made by
    :func:`identification_statuses` (dotted keys nested again, 'split' values at the top,
    'sweep_NN' statuses back into the 'sweep' list).
    """
    import ast
    out = {}
    for status in statuses:
        component, test = status.name.split("/", 1)
        values = {}
        for kv in status.values:
            _set_dotted(values, kv.key, ast.literal_eval(kv.value))
        comp = out.setdefault(component, {})
        if test == "split":
            comp.update(values)
        elif test.startswith("sweep_") and test[6:].isdigit():
            comp.setdefault("sweep", []).append(values)
        else:
            comp[test] = values
    return out


def _set_dotted(tree, key, value):
    *parents, leaf = key.split(".")
    for name in parents:
        tree = tree.setdefault(name, {})
    tree[leaf] = value


# --- vehicle --------------------------------------------------------------------------------

def mode_statuses(speeds_mps, modes):
    """DiagnosticStatus per tracked mode (weave, wobble, capsize): speeds_kmh, real [1/s],
    frequency_hz (JSON lists; null where the mode is not found)."""
    statuses = []
    for name, values in modes.items():
        values = np.asarray(values, complex)
        ok = np.isfinite(values)
        real = [float(v.real) if f else None for v, f in zip(values, ok)]
        freq = [float(v.imag / (2 * math.pi)) if f else None for v, f in zip(values, ok)]
        statuses.append(DiagnosticStatus(
            level=DiagnosticStatus.OK, name=f"vehicle/{name}", message="eigenvalue over speed",
            hardware_id="motoflex_ros", values=[
                KeyValue(key="speeds_kmh", value=json.dumps([3.6 * v for v in speeds_mps])),
                KeyValue(key="real", value=json.dumps(real)),
                KeyValue(key="frequency_hz", value=json.dumps(freq))]))
    return statuses


def series_msg(values, label):
    """std_msgs/Float64MultiArray of ``values`` (NaN where None) along one dimension named
    ``label`` (what the elements are, with units): a plot panel draws it against its index or
    against another such array (Foxglove: x axis 'path')."""
    from std_msgs.msg import Float64MultiArray, MultiArrayDimension
    data = [math.nan if v is None else float(v) for v in values]
    msg = Float64MultiArray(data=data)
    msg.layout.dim = [MultiArrayDimension(label=label, size=len(data), stride=len(data))]
    return msg


IDENTIFIED_MODELS = ("static", "torsion", "bending")
IDENTIFIED_UNITS = {"k": "N m/rad", "l": "m", "beta": "rad"}


def identified_series(result_dict):
    """{quantity: Float64MultiArray} of a component's result dict: k [N m/rad], l [m] and
    beta [rad] of the static, torsion and bending models, in that order."""
    return {q: series_msg([result_dict.get(m, {}).get(q) for m in IDENTIFIED_MODELS],
                          f"{q} [{unit}] of the models {', '.join(IDENTIFIED_MODELS)}")
            for q, unit in IDENTIFIED_UNITS.items()}


def mode_series(speeds_mps, modes):
    """{name: Float64MultiArray}: 'speed_kmh' and per tracked mode '<mode>/frequency_hz' and
    '<mode>/real_part' [1/s] over those speeds (NaN where the mode is not found): the same
    numbers as :func:`mode_statuses`, as arrays a plot panel draws against speed."""
    out = {"speed_kmh": series_msg([3.6 * v for v in speeds_mps], "speed [km/h]")}
    for name, values in modes.items():
        values = np.asarray(values, complex)
        ok = np.isfinite(values)
        out[f"{name}/frequency_hz"] = series_msg(
            [v.imag / (2 * math.pi) if f else None for v, f in zip(values, ok)],
            f"{name} frequency [Hz] at each speed of /vehicle/modes/speed_kmh")
        out[f"{name}/real_part"] = series_msg(
            [v.real if f else None for v, f in zip(values, ok)],
            f"{name} real part [1/s] at each speed of /vehicle/modes/speed_kmh")
    return out


def joint_state_msg(ns, names, positions, velocities, efforts):
    """sensor_msgs/JointState (efforts always filled: rosbags rejects Fast CDR's trailing
    padding after an empty float64[] at the end of a message)."""
    from sensor_msgs.msg import JointState
    msg = JointState(name=list(names), position=[float(v) for v in positions],
                     velocity=[float(v) for v in velocities],
                     effort=[float(v) for v in efforts])
    msg.header.stamp = time_msg(ns)
    return msg


def poses_msg(ns, frame_id, rotations, translations):
    """geometry_msgs/PoseArray of frames (rotation matrices, translations [m])."""
    msg = PoseArray()
    msg.header.stamp = time_msg(ns)
    msg.header.frame_id = frame_id
    for rot, trans in zip(rotations, translations):
        pose = Pose()
        pose.position.x, pose.position.y, pose.position.z = map(float, np.real(trans))
        x, y, z, w = quaternion_xyzw(np.real(rot))
        pose.orientation.x, pose.orientation.y = float(x), float(y)
        pose.orientation.z, pose.orientation.w = float(z), float(w)
        msg.poses.append(pose)
    return msg


def axis_marker(marker_id, frame_id, name, point, axis, length=0.5):
    """visualization_msgs/Marker: an arrow of ``length`` [m] along a joint axis through point."""
    from geometry_msgs.msg import Point
    from visualization_msgs.msg import Marker
    start = np.asarray(point, float)
    end = start + length * np.asarray(axis, float) / np.linalg.norm(axis)
    marker = Marker(ns=name, id=marker_id, type=Marker.ARROW, action=Marker.ADD)
    marker.header.frame_id = frame_id
    marker.points = [Point(x=float(a), y=float(b), z=float(c)) for a, b, c in (start, end)]
    marker.scale.x, marker.scale.y, marker.scale.z = 0.02, 0.04, 0.06
    marker.color.r, marker.color.g, marker.color.b, marker.color.a = 0.9, 0.4, 0.1, 1.0
    marker.pose.orientation.w = 1.0
    return marker


def transform_msg(ns, transform):
    """geometry_msgs/TransformStamped of a :class:`motoflex_ros.frames.FrameTransform`
    (header frame: the parent, child_frame_id: the child; what a tf2_msgs/TFMessage holds)."""
    from geometry_msgs.msg import TransformStamped
    msg = TransformStamped(child_frame_id=transform.child)
    msg.header.stamp = time_msg(ns)
    msg.header.frame_id = transform.parent
    t = msg.transform.translation
    t.x, t.y, t.z = map(float, transform.translation)
    x, y, z, w = quaternion_xyzw(transform.rotation)
    r = msg.transform.rotation
    r.x, r.y, r.z, r.w = float(x), float(y), float(z), float(w)
    return msg


def structure_markers(frame_id, name, node_xyz, elements, radius=0.004):
    """visualization_msgs/MarkerArray of a beam model: its members (LINE_LIST, one segment per
    element between its two nodes) and its nodes (SPHERE_LIST), coordinates [m] in
    ``frame_id``; ``name`` is the markers' namespace."""
    from geometry_msgs.msg import Point
    from visualization_msgs.msg import Marker, MarkerArray
    xyz = np.asarray(node_xyz, float)
    members = Marker(ns=f"{name}/members", id=0, type=Marker.LINE_LIST, action=Marker.ADD)
    members.points = [Point(x=float(a), y=float(b), z=float(c))
                      for a, b, c in xyz[np.asarray(elements, int).reshape(-1)]]
    members.scale.x = radius
    members.color.r, members.color.g, members.color.b, members.color.a = 0.6, 0.6, 0.65, 1.0
    nodes = Marker(ns=f"{name}/nodes", id=1, type=Marker.SPHERE_LIST, action=Marker.ADD)
    nodes.points = [Point(x=float(a), y=float(b), z=float(c)) for a, b, c in xyz]
    nodes.scale.x = nodes.scale.y = nodes.scale.z = 3 * radius
    nodes.color.r, nodes.color.g, nodes.color.b, nodes.color.a = 0.2, 0.4, 0.9, 1.0
    for marker in (members, nodes):
        marker.header.frame_id = frame_id
        marker.pose.orientation.w = 1.0
    return MarkerArray(markers=[members, nodes])


def qos_dict(profile):
    """The numbers of an rclpy QoSProfile as rosbag2 stores them (enum values, durations
    [ns]; :func:`motoflex_ros.record.mcap_bag.qos_yaml`)."""
    return {"history": int(profile.history.value), "depth": int(profile.depth),
            "reliability": int(profile.reliability.value),
            "durability": int(profile.durability.value),
            "deadline": profile.deadline.nanoseconds, "lifespan": profile.lifespan.nanoseconds,
            "liveliness": int(profile.liveliness.value),
            "liveliness_lease_duration": profile.liveliness_lease_duration.nanoseconds,
            "avoid_ros_namespace_conventions": bool(profile.avoid_ros_namespace_conventions)}


# --- fast paths: the bench's per-sample messages as CDR bytes ------------------------------

_CDR_LE = b"\x00\x01\x00\x00"   # encapsulation: plain CDR, little-endian


def _align(out, size):
    """Zero padding up to a multiple of ``size`` (offsets count after the 4-byte header)."""
    out += b"\0" * (-(len(out) - 4) % size)


def _header_cdr(ns, frame_id):
    """CDR of the encapsulation and a std_msgs/Header (stamp ``ns`` [ns], ``frame_id``)."""
    sec, nanosec = divmod(int(ns), NS_PER_S)
    name = frame_id.encode() + b"\0"
    out = bytearray(struct.pack("<4siII", _CDR_LE, sec, nanosec, len(name)))
    out += name
    _align(out, 4)
    return out


def _header_from_cdr(data):
    """(stamp [ns], offset after the Header) of little-endian CDR bytes."""
    sec, nanosec, length = struct.unpack_from("<iII", data, 4)
    offset = 16 + length
    return sec * NS_PER_S + nanosec, offset + (-(offset - 4) % 4)


def _doubles_cdr(ns, frame_id, values):
    out = _header_cdr(ns, frame_id)
    _align(out, 8)
    out += struct.pack(f"<{len(values)}d", *values)
    return bytes(out)


def wrench_cdr(ns, frame_id, load):
    """Serialized :func:`wrench_msg` (geometry_msgs/WrenchStamped: F_y [N] or a wrench (6,))."""
    return _doubles_cdr(ns, frame_id, _wrench_values(load))


def wrench_vector_from_cdr(data):
    """(stamp [ns], (F_x, F_y, F_z, M_x, M_y, M_z) [N, N m]) of a serialized
    geometry_msgs/WrenchStamped."""
    if data[1] != 1:  # big-endian CDR: take the slow, general path
        msg = deserialize_message(data, WrenchStamped)
        f, m = msg.wrench.force, msg.wrench.torque
        return time_ns(msg.header.stamp), (f.x, f.y, f.z, m.x, m.y, m.z)
    ns, offset = _header_from_cdr(data)
    offset += -(offset - 4) % 8
    return ns, struct.unpack_from("<6d", data, offset)


def wrench_from_cdr(data):
    """(stamp [ns], F_y [N]) of a serialized geometry_msgs/WrenchStamped."""
    ns, values = wrench_vector_from_cdr(data)
    return ns, values[1]


def pose_cdr(ns, frame_id, position, rotation):
    """Serialized :func:`pose_msg` (geometry_msgs/PoseStamped of a position [m] and a rotation
    matrix)."""
    x, y, z = (float(v) for v in position)
    return _doubles_cdr(ns, frame_id, (x, y, z, *map(float, quaternion_xyzw(rotation))))


def phase_cdr(sample=None, end_ns=None):
    """Serialized :func:`phase_msg` (std_msgs/String)."""
    data = {"end_ns": int(end_ns)} if sample is None else sample.to_dict()
    text = json.dumps(data).encode() + b"\0"
    return _CDR_LE + struct.pack("<I", len(text)) + text


def is_end_marker(phase):
    """Is a phase message (std_msgs/String or its CDR bytes) a component's end marker?"""
    if isinstance(phase, (bytes, bytearray)):
        return b'"end_ns"' in phase
    return "end_ns" in phase.data


def phase_text(msg):
    """The text of a std_msgs/String, or of its CDR bytes."""
    if not isinstance(msg, (bytes, bytearray)):
        return msg.data
    if msg[1] != 1:
        return deserialize_message(bytes(msg), String).data
    (length,) = struct.unpack_from("<I", msg, 4)
    return msg[8:7 + length].decode()


def points_cdr(ns, frame_id, points):
    """Serialized geometry_msgs/PoseArray (little-endian CDR, byte-identical to
    ``serialize_message(points_msg(ns, frame_id, points))``) without Python message objects."""
    pts = np.asarray(points, float).reshape(-1, 3)
    out = _header_cdr(ns, frame_id)
    out += struct.pack("<I", len(pts))
    if len(pts):
        _align(out, 8)
        poses = np.zeros((len(pts), 7), "<f8")
        poses[:, :3] = pts
        poses[:, 6] = 1.0
        out += poses.tobytes()
    return bytes(out)


def points_from_cdr(data):
    """(stamp [ns], points (n, 3) [m]) of a serialized geometry_msgs/PoseArray."""
    if data[1] != 1:  # big-endian CDR: take the slow, general path
        msg = deserialize_message(data, PoseArray)
        return time_ns(msg.header.stamp), points_from_msg(msg)
    ns, offset = _header_from_cdr(data)
    (count,) = struct.unpack_from("<I", data, offset)
    offset += 4
    if count:
        offset += -(offset - 4) % 8
    poses = np.frombuffer(data, "<f8", count=7 * count, offset=offset).reshape(count, 7)
    return ns, poses[:, :3].copy()
