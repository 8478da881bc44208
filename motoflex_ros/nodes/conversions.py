"""Conversions between the core's numbers (SI, numpy) and ROS 2 message objects.

Time stamps are in :mod:`.stamps`, the bench's per-sample messages as CDR bytes in :mod:`.cdr`,
the identification's and the vehicle's results in :mod:`.result_messages`.

Quaternions: :func:`motoflex_ros.spatial.quaternion_xyzw` (Shepperd's method), not scipy's
``Rotation.from_matrix(r).as_quat()``: scipy 1.17 takes about 100 us for one matrix against
2 us (and 100 us against 29 us for a batch of 12; ``benchmarks/bench_transport.py --cdr``),
and the sensor turns every sample's rotation into a quaternion (about 15,000 a campaign:
1.5 s of CPU against 0.03 s); test/test_nodes_config.py checks the two agree to 1e-15.
"""
import json

import numpy as np
from geometry_msgs.msg import Point, Pose, PoseArray, PoseStamped, TransformStamped, WrenchStamped
from sensor_msgs.msg import JointState
from std_msgs.msg import String
from visualization_msgs.msg import Marker, MarkerArray

from motoflex_ros.nodes.cdr import wrench_values
from motoflex_ros.nodes.stamps import time_msg
from motoflex_ros.spatial import quaternion_xyzw

__all__ = ["wrench_msg", "phase_msg", "points_msg", "points_from_msg", "pose_msg",
           "joint_state_msg", "poses_msg", "axis_marker", "transform_msg",
           "structure_markers", "qos_dict"]


def wrench_msg(ns, frame_id, load):
    """geometry_msgs/WrenchStamped at the loaded end: a lateral force F_y [N] (a number) or a
    wrench (F_x, F_y, F_z, M_x, M_y, M_z) [N, N m] (a moment test's torque)."""
    msg = WrenchStamped()
    msg.header.stamp = time_msg(ns)
    msg.header.frame_id = frame_id
    values = wrench_values(load)
    msg.wrench.force.x, msg.wrench.force.y, msg.wrench.force.z = values[:3]
    msg.wrench.torque.x, msg.wrench.torque.y, msg.wrench.torque.z = values[3:]
    return msg


def phase_msg(sample=None, end_ns=None):
    """std_msgs/String (JSON) with a load sample's labels (``LoadSample.to_dict``: exact
    floats), or, with ``end_ns``, the end of a component's campaign.
    """
    data = {"end_ns": int(end_ns)} if sample is None else sample.to_dict()
    return String(data=json.dumps(data))


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


def joint_state_msg(ns, names, positions, velocities, efforts):
    """sensor_msgs/JointState (efforts always filled: rosbags rejects Fast CDR's trailing
    padding after an empty float64[] at the end of a message)."""
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
