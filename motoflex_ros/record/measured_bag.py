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
import math
from pathlib import Path

import numpy as np

from motoflex_ros.identify.measurements import (
    LoadStream,
    MarkerStream,
    MeasurementError,
    check_increasing,
    synchronise,
    typical_intervals,
)

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
    return int(msg.header.stamp.sec) * 1_000_000_000 + int(msg.header.stamp.nanosec)


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


def _pose_array_frames(path, topic, n_markers):
    """(message stamps [ns], frames per message, points (frames, N, 3), message index)."""
    raw = []
    for i, msg in enumerate(_messages(path, topic)):
        points = np.array([(p.position.x, p.position.y, p.position.z) for p in msg.poses],
                          float).reshape(-1, 3)
        _finite(points, path, topic, i, lambda j, k: f"poses[{j}].position.{_AXES[k]}")
        raw.append((_stamp_ns(msg), points, i))
    sizes = [len(p) for _, p, _ in raw if len(p)]
    if not sizes:
        raise MeasurementError(path, f"topic {topic} (markers) has no marker sets")
    n = n_markers or int(np.bincount(sizes).argmax())
    if n < 3:
        raise MeasurementError(f"{path}: {topic}", f"{n} markers per frame, at least 3 "
                                                   f"needed (a rigid fit of the loaded end)")
    stamps, counts, frames, index = [], [], [], []
    for ns, points, i in raw:
        if len(points) % n:
            raise MeasurementError(f"{path}: {topic}", f"{len(points)} poses, not a whole "
                                                       f"number of frames of {n} markers",
                                   i + 1, "poses", unit="message")
        if len(points):
            stamps.append(ns)
            counts.append(len(points) // n)
            frames.append(points.reshape(-1, n, 3))
            index.append(i + 1)
    return np.array(stamps, np.int64), np.array(counts), np.concatenate(frames), index


def _spread_bursts(stamps, counts, index):
    """Frame stamps [ns]: a message with k frames stamps its last at the message's stamp and
    the others back at the stream's typical interval; frames that would not come after the
    previous message's are left out. Returns (stamps, kept mask, message index per frame)."""
    typical = typical_intervals(stamps.astype(float)) if len(stamps) > 1 else np.array([0.0])
    out, keep, rows, last = [], [], [], -math.inf
    for j, (ns, k) in enumerate(zip(stamps, counts)):
        dt = typical[min(j, len(typical) - 1)]
        for i in range(k):
            t = ns - (k - 1 - i) * dt
            ok = t > last
            keep.append(ok)
            if ok:
                out.append(t)
                rows.append(index[j])
                last = t
    return np.array(out), np.array(keep, bool), np.array(rows)


def _per_marker_frames(path, topics):
    """Frames assembled from one PointStamped/PoseStamped topic per marker (module doc)."""
    streams = []
    for topic in topics:
        stamps, points = [], []
        for i, msg in enumerate(_messages(path, topic)):
            p = msg.point if hasattr(msg, "point") else msg.pose.position
            values = np.array([[p.x, p.y, p.z]])
            _finite(values, path, topic, i, lambda _, k: f"position.{_AXES[k]}")
            stamps.append(_stamp_ns(msg))
            points.append(values[0])
        if not stamps:
            raise MeasurementError(path, f"topic {topic} (marker) has no messages")
        check_increasing(np.array(stamps, float), f"{path}: {topic}",
                         np.arange(1, len(stamps) + 1), "header.stamp", "message")
        streams.append((np.array(stamps, np.int64), np.array(points)))
    base, _ = streams[0]
    half = 0.5 * typical_intervals(base.astype(float))
    half = np.r_[half, half[-1:]] if len(half) else np.array([0.0])
    frames = np.zeros((len(base), len(streams), 3))
    ok = np.ones(len(base), bool)
    for m, (stamps, points) in enumerate(streams):
        j = np.clip(np.searchsorted(stamps, base), 1, max(len(stamps) - 1, 1))
        near = np.where(np.abs(stamps[j - 1] - base) <= np.abs(stamps[np.minimum(j, len(stamps)
                                                                                 - 1)] - base),
                        j - 1, np.minimum(j, len(stamps) - 1))
        ok &= np.abs(stamps[near] - base) <= half
        frames[:, m] = points[near]
    return base[ok], frames[ok], np.flatnonzero(ok) + 1, int(np.sum(~ok))


def read_bag(path, bench, load_topic=None, markers_topics=None):
    """Measurements of a rosbag2 folder for a BenchFile (module doc)."""
    path = Path(path)
    topics = bag_topics(path)
    load = _pick(topics, load_topic, (WRENCH,), f"/bench/{bench.name}/load", "load cell",
                 path)
    wanted = list(markers_topics or [])
    incomplete, bursts = 0, 0
    if len(wanted) > 1 or (wanted and topics.get(wanted[0]) in (POINT, POSE)):
        for topic in wanted:
            _pick(topics, topic, (POINT, POSE), None, "marker", path)
        if len(wanted) < 3:
            raise MeasurementError(path, f"{len(wanted)} marker topic(s) "
                                         f"({', '.join(wanted)}), at least 3 needed (one "
                                         f"PointStamped or PoseStamped topic per marker)")
        stamps, frames, rows, incomplete = _per_marker_frames(path, wanted)
        source = f"{path}: {', '.join(wanted)}"
    else:
        topic = _pick(topics, wanted[0] if wanted else None, (POSE_ARRAY,),
                      f"/bench/{bench.name}/markers/measured", "markers", path)
        msg_stamps, counts, frames, index = _pose_array_frames(path, topic, bench.n_markers)
        check_increasing(msg_stamps.astype(float), f"{path}: {topic}", np.array(index),
                         "header.stamp", "message")
        stamps, keep, rows = _spread_bursts(msg_stamps, counts, index)
        frames = frames[keep]
        bursts = int(np.sum(~keep))
        source = f"{path}: {topic}"
    load_ns, wrenches = _loads(path, load)
    check_increasing(load_ns.astype(float), f"{path}: {load}", np.arange(1, len(load_ns) + 1),
                     "header.stamp", "message")
    t0 = min(int(load_ns[0]), int(stamps[0]))
    loads = LoadStream((load_ns - t0) / 1e9, wrenches, f"{path}: {load}")
    markers = MarkerStream((np.asarray(stamps, float) - t0) / 1e9, frames, source, rows,
                           "message")
    data = synchronise(loads, markers, bench.latency_s)
    data.counts.update(incomplete_marker_frames=incomplete, burst_frames_left_out=bursts,
                       t0_ns=t0)
    return data


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
        ns = int(round(t * 1e9))
        return header(stamp=stamp(sec=ns // 1_000_000_000, nanosec=ns % 1_000_000_000),
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
