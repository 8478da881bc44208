"""A rig's rosbag2 recording as measurements (issue 17), read and written with rosbags.

What a real rig records: the load cell as geometry_msgs/WrenchStamped (force and torque at the
loaded end, clamp frame) and the markers either as one geometry_msgs/PoseArray per frame (a
motion-capture driver's marker set; a message holding k sets of N markers is k frames, stamped
back from its own stamp at the stream's typical interval) or as one geometry_msgs/PointStamped
or PoseStamped topic per marker (their frames are assembled by stamp: each marker's sample
nearest marker 1's stamp, within half a frame interval). Header stamps are used, never the
recording time; the streams are then synchronised by
:func:`motoflex_ros.identify.measurements.synchronise` (approximate-time matching after the
bench file's sensor latency). Topics by default: ``/bench/<bench>/load`` and
``/bench/<bench>/markers/measured`` (the emulated rig's), else the bag's only WrenchStamped and
PoseArray topics.

Problems (a missing topic, a message type that does not fit, a NaN, a stamp going back, a
marker set of the wrong size) are one MeasurementError naming the bag, the topic, the message
and the field.
"""
import functools
from pathlib import Path

import numpy as np

from motoflex_ros.identify.measurements import (
    MeasurementError,
    check_increasing,
    frames_of_marker_sets,
    frames_of_marker_streams,
    stream_measurements,
)
from motoflex_ros.units import NS_PER_S

__all__ = ["read_bag", "write_bag", "bag_topics", "WRENCH", "POSE_ARRAY", "POINT", "POSE",
           "MARKER_TYPES"]

WRENCH = "geometry_msgs/msg/WrenchStamped"
POSE_ARRAY = "geometry_msgs/msg/PoseArray"
POINT = "geometry_msgs/msg/PointStamped"
POSE = "geometry_msgs/msg/PoseStamped"
MARKER_TYPES = (POSE_ARRAY, POINT, POSE)
_AXES = "xyz"


@functools.cache
def _typestore():
    from rosbags.typesys import Stores, get_typestore
    return get_typestore(Stores.ROS2_JAZZY)


def _stamp_ns(msg):
    return int(msg.header.stamp.sec) * NS_PER_S + int(msg.header.stamp.nanosec)


def bag_topics(path):
    """{topic: message type} of a rosbag2 folder."""
    from rosbags.rosbag2 import Reader
    try:
        with Reader(path) as reader:
            return {c.topic: c.msgtype for c in reader.connections}
    except Exception as exc:   # rosbags raises its own errors for every kind of broken bag
        raise MeasurementError(path, f"not a readable rosbag2 folder: {exc}") from None


def _messages(path, topic):
    """Deserialized messages of one topic, in recording order."""
    from rosbags.rosbag2 import Reader
    store = _typestore()
    with Reader(path) as reader:
        connections = [c for c in reader.connections if c.topic == topic]
        for connection, _, raw in reader.messages(connections=connections):
            yield store.deserialize_cdr(raw, connection.msgtype)


def _pick(topics, wanted, kinds, default, what, path):
    """The topic of ``what``: given, the default if the bag has it, else the only one of its
    type; MeasurementError listing the candidates otherwise."""
    if wanted:
        if wanted not in topics:
            raise MeasurementError(path, f"no topic {wanted} ({what}); the bag has: "
                                         f"{', '.join(sorted(topics)) or 'none'}")
        if topics[wanted] not in kinds:
            raise MeasurementError(path, f"topic {wanted} ({what}) is {topics[wanted]}, "
                                         f"expected {' or '.join(kinds)}")
        return wanted
    if topics.get(default) in kinds:
        return default
    candidates = sorted(t for t, k in topics.items() if k in kinds)
    if len(candidates) == 1:
        return candidates[0]
    raise MeasurementError(path, f"no {default} and {len(candidates)} topics of type "
                                 f"{' or '.join(kinds)} ({', '.join(candidates) or 'none'}); "
                                 f"name the {what} topic (--load-topic / --markers-topic)")


def _finite(values, path, topic, index, field):
    bad = np.argwhere(~np.isfinite(values))
    if len(bad):
        raise MeasurementError(f"{path}: {topic}", f"{float(values[tuple(bad[0])])!r} is not "
                                                   f"a finite number", index + 1,
                               field(*bad[0]), unit="message")


def _loads(path, topic):
    stamps, wrenches = [], []
    for i, msg in enumerate(_messages(path, topic)):
        w = msg.wrench
        values = np.array([w.force.x, w.force.y, w.force.z, w.torque.x, w.torque.y,
                           w.torque.z])
        _finite(values[None, :], path, topic, i,
                lambda _, k: f"wrench.{'force' if k < 3 else 'torque'}.{_AXES[k % 3]}")
        stamps.append(_stamp_ns(msg))
        wrenches.append(values)
    if not stamps:
        raise MeasurementError(path, f"topic {topic} (load cell) has no messages")
    return np.array(stamps, np.int64), np.array(wrenches)


def _marker_sets(path, topic):
    """[(stamp [ns], points (k N, 3), message number)] of a PoseArray topic, checked."""
    out = []
    for i, msg in enumerate(_messages(path, topic)):
        points = np.array([(p.position.x, p.position.y, p.position.z) for p in msg.poses],
                          float).reshape(-1, 3)
        _finite(points, path, topic, i, lambda j, k: f"poses[{j}].position.{_AXES[k]}")
        out.append((_stamp_ns(msg), points, i + 1))
    return out


def _marker_stream(path, topic):
    """(stamps [ns], points (n, 3)) of a PointStamped or PoseStamped topic, checked."""
    stamps, points = [], []
    for i, msg in enumerate(_messages(path, topic)):
        p = msg.point if hasattr(msg, "point") else msg.pose.position
        values = np.array([[p.x, p.y, p.z]])
        _finite(values, path, topic, i, lambda _, k: f"position.{_AXES[k]}")
        stamps.append(_stamp_ns(msg))
        points.append(values[0])
    check_increasing(np.array(stamps, float), f"{path}: {topic}",
                     np.arange(1, len(stamps) + 1), "header.stamp", "message")
    return np.array(stamps, np.int64), np.array(points).reshape(-1, 3)


def read_bag(path, bench, load_topic=None, markers_topics=None):
    """Measurements of a rosbag2 folder for a PhysicalBench (module doc)."""
    path = Path(path)
    topics = bag_topics(path)
    load = _pick(topics, load_topic, (WRENCH,), f"/bench/{bench.name}/load", "load cell",
                 path)
    wanted = list(markers_topics or [])
    if len(wanted) > 1 or (wanted and topics.get(wanted[0]) in (POINT, POSE)):
        for topic in wanted:
            _pick(topics, topic, (POINT, POSE), None, "marker", path)
        source = f"{path}: {', '.join(wanted)}"
        stamps, frames, rows, left = frames_of_marker_streams(
            [_marker_stream(path, topic) for topic in wanted], source)
        extra = {"incomplete_marker_frames": left}
    else:
        topic = _pick(topics, wanted[0] if wanted else None, (POSE_ARRAY,),
                      f"/bench/{bench.name}/markers/measured", "markers", path)
        source = f"{path}: {topic}"
        stamps, frames, rows, left = frames_of_marker_sets(_marker_sets(path, topic),
                                                           bench.n_markers, source)
        extra = {"burst_frames_left_out": left}
    load_ns, wrenches = _loads(path, load)
    return stream_measurements(load_ns, wrenches, stamps, frames, rows, bench.latency_s,
                               f"{path}: {load}", source, extra)


def write_bag(path, load_t, wrench, marker_t, markers, load_topic, markers_topics,
              marker_type=POSE_ARRAY, frame_id="clamp"):
    """Write a rosbag2 folder (MCAP) of a rig: WrenchStamped loads at stamps load_t [s] and
    markers (n, N, 3) [m] at stamps marker_t [s], as one PoseArray topic (``markers_topics``
    one name) or one PointStamped / PoseStamped topic per marker (N names)."""
    from rosbags.rosbag2 import StoragePlugin, Writer
    store = _typestore()
    types = store.types
    header, stamp = types["std_msgs/msg/Header"], types["builtin_interfaces/msg/Time"]
    vec, point_t = types["geometry_msgs/msg/Vector3"], types["geometry_msgs/msg/Point"]
    quat, pose_t = types["geometry_msgs/msg/Quaternion"], types["geometry_msgs/msg/Pose"]

    def head(t):
        ns = int(round(t * NS_PER_S))
        return header(stamp=stamp(sec=ns // NS_PER_S, nanosec=ns % NS_PER_S),
                      frame_id=frame_id), ns

    def pose(p):
        return pose_t(position=point_t(x=float(p[0]), y=float(p[1]), z=float(p[2])),
                      orientation=quat(x=0.0, y=0.0, z=0.0, w=1.0))

    records = []
    wrench_t, wrench_msg = types[WRENCH], types["geometry_msgs/msg/Wrench"]
    for t, w in zip(load_t, wrench):
        h, ns = head(t)
        msg = wrench_t(header=h, wrench=wrench_msg(force=vec(x=w[0], y=w[1], z=w[2]),
                                                   torque=vec(x=w[3], y=w[4], z=w[5])))
        records.append((ns, load_topic, WRENCH, msg))
    for t, frame in zip(marker_t, markers):
        h, ns = head(t)
        if marker_type == POSE_ARRAY:
            records.append((ns, markers_topics[0], POSE_ARRAY,
                            types[POSE_ARRAY](header=h, poses=[pose(p) for p in frame])))
            continue
        for topic, p in zip(markers_topics, frame):
            msg = (types[POINT](header=h, point=point_t(x=p[0], y=p[1], z=p[2]))
                   if marker_type == POINT else types[POSE](header=h, pose=pose(p)))
            records.append((ns, topic, marker_type, msg))
    records.sort(key=lambda r: r[0])
    with Writer(path, version=9, storage_plugin=StoragePlugin.MCAP) as writer:
        connections = {}
        for ns, topic, kind, msg in records:
            if topic not in connections:
                connections[topic] = writer.add_connection(topic, kind, typestore=store)
            writer.write(connections[topic], ns, store.serialize_cdr(msg, kind))
    return Path(path)
