"""The vehicle_simulator node only adapts: its /vehicle/bodies are the core's world poses.

The node's road test is run with publishers that keep the messages (no DDS needed); every
PoseArray must carry frame 'odom' and, pose by pose, the core's
:func:`motoflex_ros.vehicle.poses.world_poses` of the same steer-pulse response at the same
sample, carried to the body's centre of mass (round trip through the message, quaternions
compared as rotation matrices); its transforms on /rig/tf must give the same poses by name
(odom -> vehicle -> vehicle/<body>). The node
publishes the bodies at ``bodies_rate_hz`` (50 Hz: every 4th sample of the 200 Hz response);
the core computes all samples here.
"""
import numpy as np
import pytest

pytest.importorskip("rclpy")
from scipy.spatial.transform import Rotation  # noqa: E402

from motoflex_ros.config import config_path  # noqa: E402
from motoflex_ros.frames import ODOM_FRAME as WORLD_FRAME  # noqa: E402
from motoflex_ros.nodes.road_publisher import RoadPublisher  # noqa: E402
from motoflex_ros.nodes.stamps import time_ns  # noqa: E402
from motoflex_ros.vehicle.animation import body_rows  # noqa: E402
from motoflex_ros.vehicle.linearize import linearize  # noqa: E402
from motoflex_ros.vehicle.model import load_vehicle  # noqa: E402
from motoflex_ros.vehicle.poses import world_poses  # noqa: E402
from motoflex_ros.vehicle.steer_pulse import steer_pulse_response  # noqa: E402


class KeepingPublisher:
    def __init__(self):
        self.messages = []

    def publish(self, msg):
        self.messages.append(msg)


class KeepingTf:
    def __init__(self):
        self.sent = []

    def send(self, ns, transforms):
        self.sent.append((ns, transforms))


def test_node_bodies_are_core_world_poses_roundtrip():
    model = load_vehicle(config_path("vehicles", "touring"))
    lin, speed = linearize(model), 100.0 / 3.6       # the node's default road test
    node = RoadPublisher.__new__(RoadPublisher)
    node.joints, node.bodies, node.tf = KeepingPublisher(), KeepingPublisher(), KeepingTf()
    node.clock, node.geometry, node.axes = (KeepingPublisher() for _ in range(3))
    start_ns = 30_000_000_000                          # the road test after the bench
    node.publish(lin, model, speed, 50.0, start_ns)
    pulse = steer_pulse_response(lin, speed, outputs=tuple(lin.state_names))
    poses = world_poses(lin, pulse.time, pulse.outputs, speed)   # every sample
    bodies = [b for b in model.bodies if b.mass > 0]
    frames = [lin.system.tree.body_frames[b.name] for b in bodies]
    messages = node.bodies.messages
    rows = list(range(0, len(pulse.time), 4))                    # 50 Hz of 200 Hz
    assert len(node.joints.messages) == len(pulse.time)
    # /clock at every sample of the response, on the run's clock from start_ns
    clock = [time_ns(m.clock) for m in node.clock.messages]
    assert clock == [start_ns + round(t * 1e9) for t in pulse.time]
    assert len(messages) == len(rows) and list(body_rows(pulse.time, 50.0)) == rows
    assert {m.header.frame_id for m in messages} == {WORLD_FRAME} == {"odom"}
    for i in (0, len(messages) // 3, len(messages) - 1):
        k = rows[i]
        assert time_ns(messages[i].header.stamp) == start_ns + round(pulse.time[k] * 1e9)
        ns, transforms = node.tf.sent[i]
        assert ns == time_ns(messages[i].header.stamp)
        tf = {t.child: (t.parent, t.rotation, t.translation) for t in transforms}
        assert tf["vehicle"][0] == "odom"
        base_r, base_t = tf["vehicle"][1], tf["vehicle"][2]
        for pose, frame, body in zip(messages[i].poses, frames, bodies):
            p, o = pose.position, pose.orientation
            r = poses.rotations[k, frame]
            com = r @ body.com + poses.translations[k, frame]
            np.testing.assert_allclose([p.x, p.y, p.z], com, atol=1e-12)
            np.testing.assert_allclose(Rotation.from_quat([o.x, o.y, o.z, o.w]).as_matrix(),
                                       r, atol=1e-12)
            parent, rel_r, rel_t = tf[f"vehicle/{body.name}"]
            assert parent == "vehicle"
            np.testing.assert_allclose(base_r @ rel_t + base_t, com, atol=1e-12)
            np.testing.assert_allclose(base_r @ rel_r, r, atol=1e-12)
        positions = np.array([[q.position.x, q.position.y, q.position.z]
                              for q in messages[i].poses])
        gaps = np.linalg.norm(positions[:, None] - positions[None], axis=-1)
        assert gaps[~np.eye(len(positions), dtype=bool)].min() > 0.01   # one pose per body
    # the bike runs forward in the world frame and the pulse turns its path
    last = messages[-1].poses[0].position
    assert last.x == pytest.approx(speed * pulse.time[-1], rel=0.01)
    assert abs(poses.heading[-1]) > 1e-3 and abs(last.y) > 0.1
