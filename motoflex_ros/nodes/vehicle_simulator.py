"""vehicle_simulator: the motorcycle with the identified lumped stiffness, over speed and on road.

Waits for the identified parameters of ``components`` (on /identification/results, from its
run's identification node only, or from ``result_file`` if given), builds the lumped
``variant`` of ``vehicle`` with the core (build_variant), and publishes:

- /vehicle/eigenvalues (diagnostic_msgs/DiagnosticArray): weave, wobble and capsize eigenvalues
  from ``speed_min_kmh`` to ``speed_max_kmh`` (step ``speed_step_kmh``), tracked by mode shape;
  the same numbers as arrays a plot panel draws against speed (:mod:`.mode_publisher`);
- the steer-torque pulse road test at ``road_speed_kmh`` on the run's clock, after the bench
  (:mod:`.road_publisher`: /clock, /vehicle/joint_states, /vehicle/bodies at ``bodies_rate_hz``,
  the bodies' frames on /rig/tf and their geometry on /vehicle/geometry), world -> odom on
  /rig/tf_static, and the revolute joints' axes (/vehicle/joint_axes, frame ``vehicle``: the
  main frame body's reference axes).

Then it exits 0 (the campaign waits for it).
"""
import sys
from pathlib import Path

import numpy as np
from diagnostic_msgs.msg import DiagnosticArray

from motoflex_ros.config import MOTORCYCLE_COMPONENTS
from motoflex_ros.frames import road_transform
from motoflex_ros.nodes.interfaces import LATCHED, RIG_TOPICS, TF_STATIC, Topic
from motoflex_ros.nodes.mode_publisher import MODE_TOPICS, ModePublisher
from motoflex_ros.nodes.node_main import run_node
from motoflex_ros.nodes.pacing import Waiting
from motoflex_ros.nodes.params import Param, ParameterError
from motoflex_ros.nodes.qos_profiles import latched_qos
from motoflex_ros.nodes.result_messages import results_from_statuses
from motoflex_ros.nodes.rig_node import RigNode
from motoflex_ros.nodes.road_publisher import ROAD_PAUSE_S, ROAD_TOPICS, RoadPublisher
from motoflex_ros.nodes.stamps import seconds_to_ns, time_ns
from motoflex_ros.nodes.tf import TfPublisher
from motoflex_ros.units import KMH_PER_MS

__all__ = ["VehicleSimulatorNode", "main"]


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
        *MODE_TOPICS,
        *ROAD_TOPICS, TF_STATIC,
    )

    def __init__(self):
        from motoflex_ros.config import resolve_config
        from motoflex_ros.errors import ConfigError
        from motoflex_ros.formats.component_file import load_component
        from motoflex_ros.formats.json_yaml import load_results_file
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
        self.bench_end_ns = 0   # the latest identified result's stamp: the bench's end
        self.waiting = Waiting(self)
        self.modes = ModePublisher(self)
        self.road = RoadPublisher(self)
        TfPublisher(self).static([road_transform()])
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
        self.bench_end_ns = max(self.bench_end_ns, time_ns(msg.header.stamp))

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
                           p["speed_step_kmh"]) / KMH_PER_MS
        sweep = modal_sweep(lin, speeds)
        start_ns = self.bench_end_ns + seconds_to_ns(ROAD_PAUSE_S) if self.bench_end_ns else 0
        self.modes.publish(speeds, sweep.modes, start_ns)
        self.road.publish(lin, model, p["road_speed_kmh"] / KMH_PER_MS, p["bodies_rate_hz"],
                          start_ns)
        self.get_logger().info(f"vehicle: {len(speeds)} speeds, road test published")


def main(args=None):
    """Console script ``vehicle_simulator``."""
    return run_node(VehicleSimulatorNode, args)


if __name__ == "__main__":
    sys.exit(main())
