"""Bags written by record.mcap_bag read back field by field with rosbags and mcap-ros2-support."""
import math

import pytest
import yaml

pytest.importorskip("rclpy")
from builtin_interfaces.msg import Time  # noqa: E402
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue  # noqa: E402
from geometry_msgs.msg import Pose, PoseArray, WrenchStamped  # noqa: E402
from mcap_ros2.reader import read_ros2_messages  # noqa: E402
from rclpy.serialization import serialize_message  # noqa: E402
from rosbags.highlevel import AnyReader  # noqa: E402
from rosgraph_msgs.msg import Clock  # noqa: E402
from sensor_msgs.msg import JointState  # noqa: E402

from motoflex_ros.record import mcap_bag  # noqa: E402

N = 300


def _wrench(i):
    m = WrenchStamped()
    m.header.stamp = Time(sec=i // 1000, nanosec=(i % 1000) * 1_000_000)
    m.header.frame_id = "frame_clamp"
    m.wrench.force.y = 100.0 * math.sin(0.01 * i)
    m.wrench.torque.z = -1.0e-3 * i
    return m


def _poses(i):
    m = PoseArray()
    m.header.frame_id = "frame_clamp"
    for k in range(3):
        p = Pose()
        p.position.x, p.position.y, p.position.z = 0.1 * k, 1e-6 * i, -0.5 + k
        p.orientation.w = 1.0
        m.poses.append(p)
    return m


def _joints(i):
    return JointState(name=["steer", "roll"], position=[0.01 * i, -0.02 * i],
                      velocity=[1.0, 2.0], effort=[0.5, -0.5])


def _diag(i):
    values = [KeyValue(key="k", value=repr(1.03e6 + i)), KeyValue(key="beta", value="0.5")]
    return DiagnosticArray(status=[DiagnosticStatus(level=DiagnosticStatus.OK, name="frame/static",
                                                    message="identified", values=values)])


def _clock(i):
    return Clock(clock=Time(sec=i // 1000, nanosec=(i % 1000) * 1_000_000))


TOPICS = {"/bench/frame/load": ("geometry_msgs/msg/WrenchStamped", _wrench),
          "/bench/frame/markers/true": ("geometry_msgs/msg/PoseArray", _poses),
          "/vehicle/joint_states": ("sensor_msgs/msg/JointState", _joints),
          "/identification/results": ("diagnostic_msgs/msg/DiagnosticArray", _diag),
          "/clock": ("rosgraph_msgs/msg/Clock", _clock)}


def _write_bag(path, n=N, chunk_size=4096):
    sent = {topic: [] for topic in TOPICS}
    writer = mcap_bag.BagWriter(path, chunk_size=chunk_size)
    for topic, (type_name, _) in TOPICS.items():
        writer.add_topic(topic, type_name)
    for i in range(n):
        for topic, (_, make) in TOPICS.items():
            msg = make(i)
            writer.write(topic, 1_000_000 * i + 1, serialize_message(msg))
            sent[topic].append(msg)
    return writer, sent


def _fields(msg, like=None):
    """Nested plain values of a ROS message (rclpy or rosbags), for field-by-field compare.

    Field names come from ``like`` (an rclpy message of the same type; default ``msg``).
    """
    like = msg if like is None else like
    if isinstance(msg, bytes) and len(msg) == 1:  # rclpy 'byte' fields (DiagnosticStatus.level)
        return msg[0]
    if isinstance(msg, (str, bytes, int, float)):
        return msg
    if hasattr(like, "get_fields_and_field_types"):
        return {n: _fields(getattr(msg, n), getattr(like, n))
                for n in like.get_fields_and_field_types()}
    if hasattr(msg, "item") and getattr(msg, "ndim", 0) == 0:
        return msg.item()
    return [_fields(v, w) for v, w in zip(msg, like, strict=True)]


def test_bag_roundtrip_rosbags_anyreader(tmp_path):
    bag = tmp_path / "run"
    writer, sent = _write_bag(bag)
    writer.close()
    got = {topic: [] for topic in TOPICS}
    with AnyReader([bag]) as reader:
        assert {c.topic: c.msgtype for c in reader.connections} == {
            t: ty for t, (ty, _) in TOPICS.items()}
        for conn, stamp, raw in reader.messages():
            got[conn.topic].append((stamp, reader.deserialize(raw, conn.msgtype)))
    for topic in TOPICS:
        assert len(got[topic]) == N
        for i, ((stamp, msg), ref) in enumerate(zip(got[topic], sent[topic])):
            assert stamp == 1_000_000 * i + 1
            assert _fields(msg, ref) == _fields(ref)


def test_bag_roundtrip_mcap_ros2(tmp_path):
    bag = tmp_path / "run"
    writer, sent = _write_bag(bag)
    writer.close()
    got = {topic: [] for topic in TOPICS}
    for item in read_ros2_messages(str(mcap_bag.find_mcap(bag))):
        got[item.channel.topic].append(item.ros_msg)
    for topic in TOPICS:
        assert [_fields(m, r) for m, r in zip(got[topic], sent[topic], strict=True)] == [
            _fields(r) for r in sent[topic]]


def test_bag_roundtrip_metadata_counts(tmp_path):
    bag = tmp_path / "run"
    writer, _ = _write_bag(bag, n=57)
    writer.close()
    meta = yaml.safe_load((bag / "metadata.yaml").read_text())["rosbag2_bagfile_information"]
    assert meta["message_count"] == 57 * len(TOPICS)
    assert {t["topic_metadata"]["name"]: t["message_count"]
            for t in meta["topics_with_message_count"]} == {t: 57 for t in TOPICS}
    assert meta["duration"]["nanoseconds"] == 56 * 1_000_000
    info = mcap_bag.bag_info(bag)
    assert info.message_count == 57 * len(TOPICS)
    assert info.count("/clock") == 57 and info.count("/nope") == 0
    data = [m.data for m in mcap_bag.read_messages(bag, topics=["/clock"])]
    assert data == [serialize_message(_clock(i)) for i in range(57)]


def test_bag_repair_truncated_roundtrip(tmp_path):
    bag = tmp_path / "run"
    writer, sent = _write_bag(bag, chunk_size=4096)
    writer._stream.flush()  # the writer is "killed": no finish(), no metadata.yaml
    mcap_file = writer.mcap_file
    size = mcap_file.stat().st_size
    with open(mcap_file, "r+b") as stream:  # cut in the middle of the last chunk on disk
        stream.truncate(size - 1000)
    with pytest.raises(mcap_bag.BagError, match="repair"):
        mcap_bag.bag_info(bag)
    info = mcap_bag.repair(bag)
    assert 0 < info.message_count < N * len(TOPICS)
    with AnyReader([bag]) as reader:
        counts = {}
        for conn, _, raw in reader.messages():
            msg = reader.deserialize(raw, conn.msgtype)
            k = counts.get(conn.topic, 0)
            ref = sent[conn.topic][k]
            assert _fields(msg, ref) == _fields(ref)  # a prefix of what was sent, in order
            counts[conn.topic] = k + 1
    assert counts == {t.name: t.count for t in info.topics if t.count}
    assert sum(counts.values()) == info.message_count


def test_bag_not_a_bag_is_clear_error(tmp_path):
    (tmp_path / "x.txt").write_text("hello")
    with pytest.raises(mcap_bag.BagError, match="not a bag"):
        mcap_bag.bag_info(tmp_path / "missing")
    with pytest.raises(mcap_bag.BagError, match="not a bag"):
        mcap_bag.bag_info(tmp_path)
    junk = tmp_path / "junk"
    junk.mkdir()
    (junk / "junk_0.mcap").write_bytes(b"not an mcap file at all")
    (junk / "metadata.yaml").write_text("{}")
    with pytest.raises(mcap_bag.BagError, match="not a readable MCAP"):
        mcap_bag.bag_info(junk)
    with pytest.raises(mcap_bag.BagError):
        mcap_bag.repair(junk)
    assert sorted(p.name for p in junk.iterdir()) == ["junk_0.mcap", "metadata.yaml"]


def test_bag_writer_refuses_existing_bag(tmp_path):
    bag = tmp_path / "run"
    _write_bag(bag, n=2)[0].close()
    with pytest.raises(mcap_bag.BagError, match="exists"):
        mcap_bag.BagWriter(bag)
