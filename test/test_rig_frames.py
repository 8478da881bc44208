"""The rig's frames and their way into the bag, without DDS (issue 16, points 2 and 5).

- The bench's transforms put each marker where the displacement sensor has it
  (:func:`motoflex_ros.bench.sensor.marker_positions`), in the clamp frame: at rest, and with
  the loaded end moved and turned (the moving frame on /tf carries the static markers).
- TransformStamped CDR as rclpy serializes it goes through the recorder's TfBatcher into
  tf2_msgs/msg/TFMessage that rosbags decodes to the same transforms, one message per run of
  equal stamps.
- Domain locks with namespaces: two rigs in different namespaces share a requested id, the same
  namespace twice does not, and a root-namespace run never shares.
"""
import numpy as np
import pytest

from motoflex_ros.bench.sensor import marker_positions
from motoflex_ros.frames import (
    FrameTransform,
    bench_transforms,
    clamp_frame,
    loaded_end_transform,
    marker_frame,
)
from motoflex_ros.launcher.domain import DomainBusy, DomainLock


def test_bench_markers_sit_where_the_sensor_has_them_at_rest():
    q0 = np.array([-0.6, 0.0, -0.045])
    offsets = np.array([[0, 0, 0], [0, 0.12, 0], [0, -0.12, 0], [-0.03, -0.1, 0.12]])
    from scipy.spatial.transform import Rotation
    transforms = bench_transforms([("swingarm", (0.6, 0.0, 0.36), q0, offsets),
                                   ("frame", (0.0, 0.0, 0.5), q0, offsets)])
    parent = {t.child: t for t in transforms}
    assert "swingarm_loaded_end" not in parent      # it moves: on /tf, not /tf_static
    parent["swingarm_loaded_end"] = loaded_end_transform("swingarm", q0, np.eye(3), np.zeros(3))

    def in_clamp(frame, component):
        point = np.zeros(3)
        while frame != clamp_frame(component):
            t = parent[frame]
            point, frame = t.rotation @ point + t.translation, t.parent
        return point

    expected = marker_positions(q0, np.eye(3), q0, offsets)
    for i in range(len(offsets)):
        np.testing.assert_allclose(in_clamp(marker_frame("swingarm", i), "swingarm"),
                                   expected[i], atol=1e-15)
    # the loaded end moved and turned: the markers go with it as the sensor sees them
    rotation = Rotation.from_rotvec([0.01, -0.02, 0.03]).as_matrix()
    moved = np.array([1e-3, -2e-3, 5e-4])
    parent["swingarm_loaded_end"] = loaded_end_transform("swingarm", q0, rotation, moved)
    expected = marker_positions(q0 + moved, rotation, q0, offsets)
    for i in range(len(offsets)):
        np.testing.assert_allclose(in_clamp(marker_frame("swingarm", i), "swingarm"),
                                   expected[i], atol=1e-15)
    # sorted by name, one bench spacing apart: frame first, swingarm beside it
    np.testing.assert_allclose(parent["frame_clamp"].translation, [0.0, 0.0, 0.5])
    np.testing.assert_allclose(parent["swingarm_clamp"].translation, [0.6, 1.0, 0.36])
    assert {parent[c].parent for c in ("frame_clamp", "swingarm_clamp")} == {"world"}


def test_transforms_reach_the_bag_as_tf_messages_roundtrip():
    pytest.importorskip("rclpy")
    from rclpy.serialization import serialize_message
    from rosbags.typesys import Stores, get_typestore
    from scipy.spatial.transform import Rotation

    from motoflex_ros.nodes.conversions import transform_msg
    from motoflex_ros.record.tf_bag import TF_TYPE, TfBatcher
    written = []
    batcher = TfBatcher(lambda ns, data: written.append((ns, data)))
    rotation = Rotation.from_rotvec([0.1, -0.2, 0.3]).as_matrix()
    sent = [(5, FrameTransform("odom", "vehicle", rotation, np.array([1.0, 2.0, 3.0]))),
            (5, FrameTransform("vehicle", "vehicle/frame", np.eye(3), np.array([0.5, 0, 0.6]))),
            (7, FrameTransform("odom", "vehicle", np.eye(3), np.array([2.0, 2.0, 3.0])))]
    for k, (ns, transform) in enumerate(sent):
        batcher.add(1000 + k, serialize_message(transform_msg(ns, transform)))
    assert [ns for ns, _ in written] == [1000]     # the stamp changed: the first run is out
    batcher.flush()
    batcher.flush()                                 # nothing queued: nothing written
    store = get_typestore(Stores.ROS2_JAZZY)
    decoded = [store.deserialize_cdr(data, TF_TYPE) for _, data in written]
    assert [ns for ns, _ in written] == [1000, 1002]
    got = [t for msg in decoded for t in msg.transforms]
    assert [len(m.transforms) for m in decoded] == [2, 1]
    for t, (ns, transform) in zip(got, sent):
        assert t.header.stamp.nanosec == ns and t.header.frame_id == transform.parent
        assert t.child_frame_id == transform.child
        q, p = t.transform.rotation, t.transform.translation
        np.testing.assert_allclose(Rotation.from_quat([q.x, q.y, q.z, q.w]).as_matrix(),
                                   transform.rotation, atol=1e-15)
        np.testing.assert_allclose([p.x, p.y, p.z], transform.translation, atol=0)


def test_namespaced_rigs_share_a_domain_id_and_nothing_else(tmp_path):
    with DomainLock(tmp_path, domain_id=7, namespace="/rig_a"):
        with DomainLock(tmp_path, domain_id=7, namespace="rig_b/") as b:
            assert b.domain_id == 7
        with pytest.raises(DomainBusy, match="namespace /rig_a"):
            DomainLock(tmp_path, domain_id=7, namespace="/rig_a").acquire()
        with pytest.raises(DomainBusy):
            DomainLock(tmp_path, domain_id=7).acquire()         # the root would meet both
    with DomainLock(tmp_path, domain_id=7):
        with pytest.raises(DomainBusy):
            DomainLock(tmp_path, domain_id=7, namespace="/rig_a").acquire()
    with DomainLock(tmp_path, domain_id=7, namespace="/rig_a"):   # all released
        pass
