"""The bench's per-sample messages as CDR bytes, written and read without message objects.

Phase (std_msgs/String of JSON), load (geometry_msgs/WrenchStamped), markers
(geometry_msgs/PoseArray), pose (geometry_msgs/PoseStamped) and /clock: little-endian CDR as
rclpy's serializer writes it, padding zeroed, byte-identical to
``rclpy.serialization.serialize_message`` of the same message (test/test_nodes_config.py
checks each against it); big-endian input takes rclpy's deserializer.

Why by hand (measured on this machine with ``benchmarks/bench_transport.py --cdr``): the graph
handles about 11,500 samples a campaign, each written once and read by two to three nodes,
and building a message object and serializing it, or deserializing it into one, costs 4-32x
the bytes' own path (one PoseArray of 6 markers: 4.5 us written here against 44 us through
``points_msg`` and ``serialize_message``, read 1.8 us against 53 us; a WrenchStamped read
0.5 us against 17 us).
"""
import json
import struct

import numpy as np
from geometry_msgs.msg import PoseArray, WrenchStamped
from rclpy.serialization import deserialize_message
from rosgraph_msgs.msg import Clock
from std_msgs.msg import String

from motoflex_ros.bench.actuator import LATERAL_WRENCH, LoadSample, wrench_amplitude
from motoflex_ros.nodes.stamps import time_ns
from motoflex_ros.spatial import quaternion_xyzw
from motoflex_ros.units import NS_PER_S

__all__ = ["clock_ns_from_cdr", "wrench_values", "wrench_cdr", "wrench_vector_from_cdr",
           "wrench_from_cdr", "pose_cdr", "phase_cdr", "phase_text", "is_end_marker",
           "sample_from_phase", "points_cdr", "points_from_cdr"]


def clock_ns_from_cdr(data):
    """Simulated time [ns] of a serialized rosgraph_msgs/Clock (fast path: little-endian)."""
    if len(data) >= 12 and data[1] == 1:
        sec, nanosec = struct.unpack_from("<iI", data, 4)
        return sec * NS_PER_S + nanosec
    return time_ns(deserialize_message(data, Clock).clock)


def wrench_values(load):
    """(F_x, F_y, F_z, M_x, M_y, M_z) of a lateral force F_y [N] (a number) or a wrench (6,)."""
    if np.ndim(load) == 0:
        return (0.0, float(load), 0.0, 0.0, 0.0, 0.0)
    return tuple(float(v) for v in load)


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
    return _doubles_cdr(ns, frame_id, wrench_values(load))


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
        return time_ns(msg.header.stamp), np.array(
            [(p.position.x, p.position.y, p.position.z) for p in msg.poses], float).reshape(-1, 3)
    ns, offset = _header_from_cdr(data)
    (count,) = struct.unpack_from("<I", data, offset)
    offset += 4
    if count:
        offset += -(offset - 4) % 8
    poses = np.frombuffer(data, "<f8", count=7 * count, offset=offset).reshape(count, 7)
    return ns, poses[:, :3].copy()
