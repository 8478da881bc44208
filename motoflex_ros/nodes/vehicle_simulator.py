"""vehicle_simulator: the motorcycle with the identified lumped stiffness, over speed and on road.

Waits for the identified parameters of ``components`` (on /identification/results, from its
run's identification node only, or from ``result_file`` if given), builds the lumped
``variant`` of ``vehicle`` with the core (build_variant), and publishes:

- /vehicle/eigenvalues (diagnostic_msgs/DiagnosticArray): weave, wobble and capsize eigenvalues
  from ``speed_min_kmh`` to ``speed_max_kmh`` (step ``speed_step_kmh``), tracked by mode shape;
  the same numbers as arrays a plot panel draws against speed (std_msgs/Float64MultiArray,
  latched): /vehicle/modes/speed_kmh and /vehicle/modes/<mode>/{frequency_hz, real_part};
- the steer-torque pulse road test at ``road_speed_kmh``: /vehicle/joint_states
  (sensor_msgs/JointState: joint angles, rates, applied torques; every sample of the response,
  200 Hz) and /vehicle/bodies (geometry_msgs/PoseArray: the pose of each body with mass at its
  centre of mass, in the world frame ``odom``: x forward along the initial heading, the bike's
  path and heading integrated by the core over every sample,
  :func:`motoflex_ros.vehicle.poses.world_poses`) at ``bodies_rate_hz`` (default 50 Hz: enough
  to watch the weave, and the poses, a nonlinear position solve per body pose sample, cost a
  quarter), stamped with the road-test time; the same poses as named frames on /rig/tf
  (odom -> vehicle -> vehicle/<body>, in the PoseArray's order; recorded as /tf,
  :mod:`motoflex_ros.frames`) and world -> odom on /rig/tf_static;
- /vehicle/joint_axes (visualization_msgs/Marker, one per revolute joint, latched, in the
  frame ``vehicle``: the main frame body's reference axes).

Then it exits 0 (the campaign waits for it).
"""
import sys
from pathlib import Path

import numpy as np
from diagnostic_msgs.msg import DiagnosticArray
from geometry_msgs.msg import PoseArray
from sensor_msgs.msg import JointState
from std_msgs.msg import Float64MultiArray
from visualization_msgs.msg import Marker

from motoflex_ros.config import MOTORCYCLE_COMPONENTS
from motoflex_ros.frames import (
    ODOM_FRAME,
    VEHICLE_FRAME,
    body_com_poses,
    road_transform,
    vehicle_transforms,
)
from motoflex_ros.nodes.conversions import (
    axis_marker,
    joint_state_msg,
    mode_series,
    mode_statuses,
    poses_msg,
    results_from_statuses,
    seconds_to_ns,
)
from motoflex_ros.nodes.interfaces import (
    LATCHED,
    LATCHED_LAST,
    RELIABLE,
    RIG_TOPICS,
    TF_DYNAMIC,
    TF_STATIC,
    Topic,
)
from motoflex_ros.nodes.pacing import Waiting
from motoflex_ros.nodes.params import Param, ParameterError
from motoflex_ros.nodes.runtime import RigNode, latched_qos, publish_patiently, run_node
from motoflex_ros.nodes.tf import TfPublisher

__all__ = ["VehicleSimulatorNode", "main", "body_rows"]

FRAME = VEHICLE_FRAME
WORLD_FRAME = ODOM_FRAME


class VehicleSimulatorNode(RigNode):
    """Identified parameters in, stability and road test out."""

    NAME = "vehicle_simulator"
    ENDS_ITSELF = True
    PARAMS = (
        Param("components", MOTORCYCLE_COMPONENTS,
              description="components whose identified models go into the vehicle"),
        Param("vehicle", "touring", description="vehicle name or YAML file"),
        Param("variant", "static", choices=("static", "torsion", "bending", "decomposed"),
              description="lumped variant (paper Sect. 5.2)"),
        Param("result_file", "", description="identify-format results ('': the topic)"),
        Param("speed_min_kmh", 40.0, 1.0, 400.0, description="lowest speed [km/h]"),
        Param("speed_max_kmh", 210.0, 1.0, 400.0, description="highest speed [km/h]"),
        Param("speed_step_kmh", 5.0, 0.1, 100.0, description="speed step [km/h]"),
        Param("road_speed_kmh", 100.0, 1.0, 400.0, description="road-test speed [km/h]"),
        Param("bodies_rate_hz", 50.0, 0.1, 1000.0,
              description="rate of /vehicle/bodies [Hz] (at most the response's 200 Hz)"),
    )
    TOPICS = RIG_TOPICS + (
        Topic("sub", "identification/results", "diagnostic_msgs/msg/DiagnosticArray", LATCHED,
              "the identified parameters, from its run's identification node only",
              when="result_file ''"),
        Topic("pub", "vehicle/eigenvalues", "diagnostic_msgs/msg/DiagnosticArray", LATCHED,
              "weave, wobble and capsize over speed (KeyValue JSON lists speeds_kmh, real "
              "[1/s], frequency_hz), tracked by mode shape"),
        Topic("pub", "vehicle/modes/speed_kmh", "std_msgs/msg/Float64MultiArray", LATCHED_LAST,
              "the speeds of the sweep [km/h]", when="after the sweep"),
        Topic("pub", "vehicle/modes/{c}/frequency_hz", "std_msgs/msg/Float64MultiArray",
              LATCHED_LAST, "a mode's frequency over speed [Hz] ({c}: weave, wobble, capsize)",
              when="after the sweep"),
        Topic("pub", "vehicle/modes/{c}/real_part", "std_msgs/msg/Float64MultiArray",
              LATCHED_LAST, "a mode's real part over speed [1/s] ({c}: weave, wobble, capsize)",
              when="after the sweep"),
        Topic("pub", "vehicle/joint_states", "sensor_msgs/msg/JointState", RELIABLE,
              "road test: joint angles [rad or m], rates, applied torques, 200 Hz"),
        Topic("pub", "vehicle/bodies", "geometry_msgs/msg/PoseArray", RELIABLE,
              "road test: each body's centre-of-mass pose, frame odom, bodies_rate_hz"),
        Topic("pub", "vehicle/joint_axes", "visualization_msgs/msg/Marker", LATCHED,
              "one arrow per revolute joint, frame vehicle"),
        TF_DYNAMIC, TF_STATIC,
    )

    def __init__(self):
        from motoflex_ros.config import resolve_config
        from motoflex_ros.errors import ConfigError
        from motoflex_ros.identify.results import load_results_file
        from motoflex_ros.structures import load_component
        from motoflex_ros.vehicle.model import load_vehicle
        super().__init__()
        p = self.params
        if p["speed_min_kmh"] > p["speed_max_kmh"]:
            raise ParameterError(f"node '{self.get_name()}': parameter 'speed_min_kmh' = "
                                 f"{p['speed_min_kmh']:g} is above 'speed_max_kmh' = "
                                 f"{p['speed_max_kmh']:g} (expected speed_min_kmh <= "
                                 f"speed_max_kmh: no speed to compute)")
        self.rigid = load_vehicle(resolve_config("vehicles", p["vehicle"]))
        self.components = {n: load_component(n) for n in p["components"]}
        self.identified = {}
        self.waiting = Waiting(self)
        self.eig_pub = self.create_publisher(DiagnosticArray, "vehicle/eigenvalues",
                                             latched_qos())
        self.joints_pub = self.advertise(JointState, "vehicle/joint_states")
        self.bodies_pub = self.advertise(PoseArray, "vehicle/bodies")
        self.axes_pub = self.create_publisher(Marker, "vehicle/joint_axes", latched_qos())
        self.tf = TfPublisher(self, dynamic=True)
        self.series_pubs = []
        self.tf.static([road_transform()])
        if p["result_file"]:
            try:
                self.identified = load_results_file(Path(p["result_file"]), p["components"])
            except ConfigError as exc:
                raise ParameterError(f"node '{self.get_name()}': parameter 'result_file': "
                                     f"{exc}") from None
        else:
            self.subscribe(DiagnosticArray, "identification/results", self._on_results,
                           qos=latched_qos(), publishers=("identification",))

    def _on_results(self, msg):
        self.identified.update(results_from_statuses(msg.status))

    def inputs_ready(self):
        """Ready at once: the results come when the bench is done."""
        return True

    def step(self, spinner):
        """Wait for every component's results, then compute and publish, then finish."""
        self.announce_ready()
        missing = [n for n in self.params["components"] if n not in self.identified]
        if missing:
            self.waiting.still(f"the identified results of {', '.join(missing)} on "
                               "/identification/results")
            spinner.spin_once(0.1)
            return
        self._simulate()
        self.finished = True

    def _simulate(self):
        from motoflex_ros.study.identified_variants import build_variant
        from motoflex_ros.vehicle.linearize import linearize
        from motoflex_ros.vehicle.modes import modal_sweep
        p = self.params
        names = list(p["components"])
        model = build_variant(self.rigid, p["variant"], names, self.identified,
                              self.components)
        lin = linearize(model)
        speeds = np.arange(p["speed_min_kmh"], p["speed_max_kmh"] + 1e-9,
                           p["speed_step_kmh"]) / 3.6
        sweep = modal_sweep(lin, speeds)
        self.eig_pub.publish(DiagnosticArray(status=mode_statuses(speeds, sweep.modes)))
        for name, series in mode_series(speeds, sweep.modes).items():
            pub = self.create_publisher(Float64MultiArray, f"vehicle/modes/{name}",
                                        latched_qos(1))
            pub.publish(series)
            self.series_pubs.append(pub)
        for k, joint in enumerate(j for j in model.joints if j.kind == "revolute"):
            self.axes_pub.publish(axis_marker(k, FRAME, joint.name, joint.point, joint.axis))
        self._road_test(lin, model, p["road_speed_kmh"] / 3.6, p["bodies_rate_hz"])
        self.get_logger().info(f"vehicle: {len(speeds)} speeds, road test published")

    def _road_test(self, lin, model, speed, bodies_rate_hz):
        from motoflex_ros.vehicle.kinematics import BASE_NAMES
        from motoflex_ros.vehicle.poses import world_poses
        from motoflex_ros.vehicle.steer_pulse import steer_pulse_response
        names = tuple(lin.state_names)
        pulse = steer_pulse_response(lin, speed, outputs=names)
        rows = body_rows(pulse.time, bodies_rate_hz)
        poses = world_poses(lin, pulse.time, pulse.outputs, speed, rows)
        pose_of_row = {int(row): i for i, row in enumerate(rows)}
        tree = lin.system.tree
        coords = [c.name for c in tree.coordinates]
        joints = [n for n in names if n in coords and f"{n}_rate" in names]
        steer = model.roles.get("steer", "steer")
        bodies = [b for b in model.bodies if b.mass > 0]
        frames = [tree.body_frames[b.name] for b in bodies]
        coms = [b.com for b in bodies]
        base = len(BASE_NAMES)   # the frame the base chain moves: the main frame body's
        for k, (row, t) in enumerate(zip(pulse.outputs, pulse.time)):
            values = dict(zip(names, row))
            ns = seconds_to_ns(t)
            torque = pulse.torque if t < pulse.duration else 0.0
            efforts = [torque if j == steer else 0.0 for j in joints]
            publish_patiently(self.joints_pub, joint_state_msg(
                ns, joints, [values[j] for j in joints], [values[f"{j}_rate"] for j in joints],
                efforts))
            i = pose_of_row.get(k)
            if i is not None:
                rotations, positions = body_com_poses(poses.rotations[i, frames],
                                                      poses.translations[i, frames], coms)
                publish_patiently(self.bodies_pub, poses_msg(ns, WORLD_FRAME, rotations,
                                                             positions))
                self.tf.send(ns, vehicle_transforms(
                    poses.rotations[i, base], poses.translations[i, base],
                    [b.name for b in bodies], rotations, positions))


def body_rows(time, rate_hz):
    """Indices of the response samples (``time`` [s], uniform) published on /vehicle/bodies at
    about ``rate_hz`` [Hz]: every n-th sample, n = round(1 / (rate_hz dt)) >= 1, from the first."""
    dt = (time[-1] - time[0]) / (len(time) - 1) if len(time) > 1 else 1.0
    return np.arange(0, len(time), max(1, int(round(1.0 / (rate_hz * dt)))))


def main(args=None):
    """Console script ``vehicle_simulator``."""
    return run_node(VehicleSimulatorNode, args)


if __name__ == "__main__":
    sys.exit(main())
