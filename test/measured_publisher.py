"""A rig's publisher for test_measured_live (issue 17), run as a process of its own.

``python measured_publisher.py STREAMS.npz BENCH [points]``: publishes the load cell
(geometry_msgs/WrenchStamped on /bench/BENCH/load) and the marker sets (geometry_msgs/PoseArray
on /bench/BENCH/markers/measured) of the .npz (load_t, wrench, marker_t, markers, send_t: when
each message goes out, loads first then markers), in the order of send_t, as fast as the
readers take them; then asks for the identification (std_msgs/Empty on /bench/BENCH/identify)
once every message is acknowledged. With ``points``: the loads on /ati/wrench and one
geometry_msgs/PointStamped topic per marker, /vicon/BENCH/m1, /m2, ... (a motion-capture
driver's convention). It waits for the identification node's /rig/ready and for
its readers, with no deadline (the test's hang guard ends a run that never starts).
"""
import sys
import time

import numpy as np
import rclpy
from geometry_msgs.msg import PointStamped, Pose, PoseArray, WrenchStamped
from rclpy.duration import Duration
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
from std_msgs.msg import Empty, String


def _stamp(msg, t):
    ns = int(round(t * 1e9))
    msg.header.stamp.sec, msg.header.stamp.nanosec = ns // 10**9, ns % 10**9
    msg.header.frame_id = "clamp"
    return msg


def _wrench(t, w):
    msg = _stamp(WrenchStamped(), t)
    f, m = msg.wrench.force, msg.wrench.torque
    f.x, f.y, f.z, m.x, m.y, m.z = (float(v) for v in w)
    return msg


def _markers(t, points):
    msg = _stamp(PoseArray(), t)
    for x, y, z in points:
        pose = Pose()
        pose.position.x, pose.position.y, pose.position.z = float(x), float(y), float(z)
        pose.orientation.w = 1.0
        msg.poses.append(pose)
    return msg


def _point(t, p):
    msg = _stamp(PointStamped(), t)
    msg.point.x, msg.point.y, msg.point.z = (float(v) for v in p)
    return msg


def _publish(publisher, msg):
    while True:
        try:
            publisher.publish(msg)
            return
        except Exception as exc:   # a full keep-all reader: try again
            if "cannot publish" not in str(exc):
                raise
            time.sleep(0.001)


def main(npz, bench, layout="posearray"):
    data = np.load(npz)
    rclpy.init()
    node = rclpy.create_node("rig_publisher")
    qos = QoSProfile(depth=1, history=HistoryPolicy.KEEP_ALL,
                     reliability=ReliabilityPolicy.RELIABLE)
    points = layout == "points"
    loads = node.create_publisher(WrenchStamped, "/ati/wrench" if points
                                  else f"/bench/{bench}/load", qos)
    if points:
        per_marker = [node.create_publisher(PointStamped, f"/vicon/{bench}/m{i + 1}", qos)
                      for i in range(data["markers"].shape[1])]
    else:
        per_marker = [node.create_publisher(PoseArray, f"/bench/{bench}/markers/measured",
                                            qos)]
    ask = node.create_publisher(Empty, f"/bench/{bench}/identify", qos)
    ready = []
    latched = QoSProfile(depth=100, history=HistoryPolicy.KEEP_LAST,
                         reliability=ReliabilityPolicy.RELIABLE,
                         durability=DurabilityPolicy.TRANSIENT_LOCAL)
    node.create_subscription(String, "/rig/ready", lambda m: ready.append(m.data), latched)
    while "identification" not in ready or min(p.get_subscription_count()
                                               for p in (loads, *per_marker, ask)) < 1:
        rclpy.spin_once(node, timeout_sec=0.05)
    n_loads = len(data["load_t"])
    for k in np.argsort(data["send_t"], kind="stable"):
        if k < n_loads:
            _publish(loads, _wrench(data["load_t"][k], data["wrench"][k]))
        elif points:
            j = k - n_loads
            for publisher, p in zip(per_marker, data["markers"][j]):
                _publish(publisher, _point(data["marker_t"][j], p))
        else:
            j = k - n_loads
            _publish(per_marker[0], _markers(data["marker_t"][j], data["markers"][j]))
    for publisher in (loads, *per_marker):
        while not publisher.wait_for_all_acked(Duration(seconds=1.0)):
            pass
    _publish(ask, Empty())
    while not ask.wait_for_all_acked(Duration(seconds=1.0)):
        pass
    node.destroy_node()
    rclpy.shutdown()


if __name__ == "__main__":
    main(*sys.argv[1:])
