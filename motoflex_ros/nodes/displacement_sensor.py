"""displacement_sensor: the marker sensor (noise, resolution, latency) of the bench.

For each sample (phase + true markers of /bench/<c>/) the core's MarkerSensor captures the
true markers (noise, resolution, latency) and the node publishes what the sensor delivers at
that sample: all delivered marker sets in one
/bench/<c>/markers/measured (geometry_msgs/PoseArray, possibly empty while the latency runs)
and, per delivered measurement, the fitted pose on /bench/<c>/pose (PoseStamped). At the end
marker it flushes the sensor. True markers that are not finite or stamped before the previous
ones stop the node (:mod:`.message_checks`).
"""
import sys

import numpy as np
from geometry_msgs.msg import PoseArray, PoseStamped
from std_msgs.msg import String

from motoflex_ros.bench.sensor import MarkerSensor
from motoflex_ros.nodes.bench_graph import BENCH_PARAMS, SampleJoin, campaign_setups, frame_id
from motoflex_ros.nodes.bench_graph import topic as bench_topic
from motoflex_ros.nodes.cdr import is_end_marker, points_cdr, pose_cdr, sample_from_phase
from motoflex_ros.nodes.interfaces import PHASE_IN, RELIABLE, RIG_TOPICS, Topic
from motoflex_ros.nodes.message_checks import BenchInputs
from motoflex_ros.nodes.node_main import run_node
from motoflex_ros.nodes.rig_node import RigNode

__all__ = ["DisplacementSensorNode", "main"]


class DisplacementSensorNode(RigNode):
    """True markers in, measured markers and pose out."""

    NAME = "displacement_sensor"
    PARAMS = BENCH_PARAMS
    TOPICS = RIG_TOPICS + (
        PHASE_IN,
        Topic("sub", "bench/{c}/markers/true", "geometry_msgs/msg/PoseArray", RELIABLE,
              "true marker positions [m]"),
        Topic("pub", "bench/{c}/markers/measured", "geometry_msgs/msg/PoseArray", RELIABLE,
              "measured marker positions [m] (noise, resolution, rate, latency), frame "
              "<c>_clamp"),
        Topic("pub", "bench/{c}/pose", "geometry_msgs/msg/PoseStamped", RELIABLE,
              "pose of the loaded end from a rigid fit of the measured markers, frame "
              "<c>_clamp"),
    )

    def __init__(self):
        super().__init__()
        self.setups = campaign_setups(self.params)
        seed = self.params["seed"]
        self.sensors = {c: MarkerSensor(s.protocol.sensor, s.reduced.q0, seed)
                        for c, s in self.setups.items()}
        self.measured_pubs, self.pose_pubs, self.offsets = {}, {}, {}
        for c in self.setups:
            self.measured_pubs[c] = self.advertise(PoseArray, bench_topic(c, "markers/measured"))
            self.pose_pubs[c] = self.advertise(PoseStamped, bench_topic(c, "pose"))
            join = SampleJoin("phase", ("true",), self._handler(c),
                              needs=lambda head: () if is_end_marker(head) else ("true",))
            self.subscribe(String, bench_topic(c, "phase"), join.callback("phase"), raw=True)
            self.subscribe(PoseArray, bench_topic(c, "markers/true"), join.callback("true"),
                           raw=True)

    def _handler(self, component):
        sensor = self.sensors[component]
        frame = frame_id(component)
        checked = BenchInputs.of_plan(component, self.setups[component].plan,
                                      self.get_namespace())

        def handle(phase, inputs):
            if "true" not in inputs:
                _, ns = sample_from_phase(phase, 0.0)
                delivered = sensor.flush()
            else:
                sample, _ = sample_from_phase(phase, 0.0)
                ns, true_markers = checked.markers("markers/true", inputs["true"])
                delivered = sensor.capture_markers(sample.index, sample.t, true_markers)
            markers = [m.markers for m in delivered]
            self.measured_pubs[component].publish(
                points_cdr(ns, frame, np.concatenate(markers) if markers else np.zeros((0, 3))))
            for m in delivered:
                self.pose_pubs[component].publish(pose_cdr(ns, frame, m.position, m.rotation))
        return handle


def main(args=None):
    """Console script ``displacement_sensor``."""
    return run_node(DisplacementSensorNode, args)


if __name__ == "__main__":
    sys.exit(main())
