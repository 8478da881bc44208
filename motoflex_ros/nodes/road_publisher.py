"""The vehicle_simulator's road test on the run's one simulated clock.

The steer-torque pulse response comes from the core (:func:`motoflex_ros.vehicle.animation.
road_test`, true size, its poses at ``bodies_rate_hz``). It starts ``ROAD_PAUSE_S`` after the
latest identified result's stamp (the end of the last bench test; 0 from a result file) and
goes out stamped on that clock, with /clock at every response sample so the recorded clock
covers it: /vehicle/joint_states (every sample, 200 Hz), /vehicle/bodies (each body's
centre-of-mass pose in ``odom``), the same poses as frames on /rig/tf (odom -> vehicle ->
vehicle/<body>, :mod:`motoflex_ros.frames`) and, latched, the bodies' geometry on those frames
(/vehicle/geometry, visualization_msgs/MarkerArray: :mod:`.rig_markers`) and the revolute
joints' axes (/vehicle/joint_axes, visualization_msgs/Marker, frame ``vehicle``).
"""
from geometry_msgs.msg import PoseArray
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import JointState
from visualization_msgs.msg import Marker, MarkerArray

from motoflex_ros.frames import ODOM_FRAME, VEHICLE_FRAME, body_com_poses, vehicle_transforms
from motoflex_ros.nodes.conversions import axis_marker, joint_state_msg, poses_msg
from motoflex_ros.nodes.interfaces import LATCHED, LATCHED_LAST, RELIABLE, TF_DYNAMIC, Topic
from motoflex_ros.nodes.qos_profiles import latched_qos
from motoflex_ros.nodes.rig_markers import motorcycle_markers
from motoflex_ros.nodes.stamps import clock_msg, seconds_to_ns, time_msg
from motoflex_ros.nodes.tf import TfPublisher
from motoflex_ros.nodes.transport import publish_patiently

__all__ = ["RoadPublisher", "ROAD_TOPICS", "ROAD_PAUSE_S"]

ROAD_PAUSE_S = 0.1
ROAD_TOPICS = (
    Topic("pub", "clock", "rosgraph_msgs/msg/Clock", RELIABLE,
          "simulated time during the road test, at every response sample (after the bench's)"),
    Topic("pub", "vehicle/joint_states", "sensor_msgs/msg/JointState", RELIABLE,
          "road test: joint angles [rad or m], rates, applied torques, 200 Hz"),
    Topic("pub", "vehicle/bodies", "geometry_msgs/msg/PoseArray", RELIABLE,
          "road test: each body's centre-of-mass pose, frame odom, bodies_rate_hz"),
    Topic("pub", "vehicle/joint_axes", "visualization_msgs/msg/Marker", LATCHED,
          "one arrow per revolute joint, frame vehicle (frame_locked)"),
    Topic("pub", "vehicle/geometry", "visualization_msgs/msg/MarkerArray", LATCHED_LAST,
          "the bodies' linkage, centres of mass and tyres, each on its frame vehicle/<body> "
          "(frame_locked)"),
    TF_DYNAMIC,
)


class RoadPublisher:
    """The road test's publishers on ``node``; :meth:`publish` sends one road test."""

    def __init__(self, node):
        self.clock = node.advertise(Clock, "clock")
        self.joints = node.advertise(JointState, "vehicle/joint_states")
        self.bodies = node.advertise(PoseArray, "vehicle/bodies")
        self.geometry = node.create_publisher(MarkerArray, "vehicle/geometry", latched_qos(1))
        self.axes = node.create_publisher(Marker, "vehicle/joint_axes", latched_qos())
        self.tf = TfPublisher(node, dynamic=True)

    def publish(self, lin, model, speed, bodies_rate_hz, start_ns):
        """The steer-pulse road test of ``lin`` (of VehicleModel ``model``) at ``speed``
        [m/s], from ``start_ns`` [ns] of simulated time."""
        from motoflex_ros.vehicle.animation import road_test
        from motoflex_ros.vehicle.kinematics import BASE_NAMES
        road = road_test(lin, speed, None, bodies_rate_hz)
        self.geometry.publish(motorcycle_markers(model, start_ns))
        for k, joint in enumerate(j for j in model.joints if j.kind == "revolute"):
            marker = axis_marker(k, VEHICLE_FRAME, joint.name, joint.point, joint.axis)
            marker.header.stamp, marker.frame_locked = time_msg(start_ns), True
            self.axes.publish(marker)
        names = list(road.state_names)
        coords = {c.name for c in lin.system.tree.coordinates}
        joints = [n for n in names if n in coords and f"{n}_rate" in names]
        angles = road.states[:, [names.index(j) for j in joints]]
        rates = road.states[:, [names.index(f"{j}_rate") for j in joints]]
        efforts = road.efforts(joints, model.roles.get("steer", "steer"))
        bodies = [b for b in model.bodies if b.mass > 0]
        frames = [lin.system.tree.body_frames[b.name] for b in bodies]
        base = len(BASE_NAMES)   # the frame the base chain moves: the main frame body's
        pose_of_row = {int(row): i for i, row in enumerate(road.rows)}
        for k, t in enumerate(road.time):
            ns = start_ns + seconds_to_ns(t)
            publish_patiently(self.clock, clock_msg(ns))
            publish_patiently(self.joints, joint_state_msg(ns, joints, angles[k], rates[k],
                                                           efforts[k]))
            i = pose_of_row.get(k)
            if i is not None:
                rotations, positions = body_com_poses(road.rotations[i, frames],
                                                      road.translations[i, frames],
                                                      [b.com for b in bodies])
                publish_patiently(self.bodies, poses_msg(ns, ODOM_FRAME, rotations, positions))
                self.tf.send(ns, vehicle_transforms(
                    road.rotations[i, base], road.translations[i, base],
                    [b.name for b in bodies], rotations, positions))
