"""identification: identifies each component's lumped models from loads and measured poses.

Per sample it pairs the phase and load (/bench/<c>/phase, /load) with what the sensor delivered
(/bench/<c>/markers/measured), refits the pose of each delivered marker set (core rigid fit)
and feeds the core's streaming Identifier, then acknowledges the sample on /rig/ack (adding
'settled <test>' when a harmonic test's mean has settled, so the actuator ends that test). At a
component's end marker it computes l, beta, b, k, c, J, k_t, k_b (core identify_component),
publishes them on /identification/results (diagnostic_msgs/DiagnosticArray, one status per
test, KeyValue values), the same k [N m/rad], l [m] and beta [rad] of the static, torsion and
bending models as numbers a plot panel draws on /identification/<c>/{k, l, beta}
(std_msgs/Float64MultiArray, latched) and, once every component is done, writes
``result_file`` atomically.
Loads and measured markers that are not finite, loads beyond the protocol's range and stamps
that go back stop the node at that message (:mod:`.message_checks`), before the core sees it.
"""
import sys

import numpy as np
from diagnostic_msgs.msg import DiagnosticArray, KeyValue
from geometry_msgs.msg import PoseArray, WrenchStamped
from std_msgs.msg import Float64MultiArray, String

from motoflex_ros.nodes.bench_graph import BENCH_PARAMS, SampleJoin, campaign_setups
from motoflex_ros.nodes.bench_graph import topic as bench_topic
from motoflex_ros.nodes.conversions import (
    IDENTIFIED_UNITS,
    identification_statuses,
    identified_series,
    is_end_marker,
    sample_from_phase,
    time_msg,
)
from motoflex_ros.nodes.load_actuator import may_end_test
from motoflex_ros.nodes.message_checks import BenchInputs
from motoflex_ros.nodes.params import Param
from motoflex_ros.nodes.runtime import ACK_TOPIC, RigNode, latched_qos, run_node
from motoflex_ros.results_file import write_results

__all__ = ["IdentificationNode", "main", "RESULTS_TOPIC"]

RESULTS_TOPIC = "identification/results"


class IdentificationNode(RigNode):
    """Loads and measurements in, identified models out."""

    NAME = "identification"
    PARAMS = BENCH_PARAMS + (
        Param("result_file", "", description="JSON file of the results ('': none)"),
        Param("exit_when_done", False, description="exit once every component is identified"),
    )

    def __init__(self):
        from motoflex_ros.bench.sensor import MarkerSensor
        from motoflex_ros.identify.identifier import Identifier
        super().__init__()
        self.setups = campaign_setups(self.params)
        self.ENDS_ITSELF = self.params["exit_when_done"]   # a job to finish: replay --identify
        self.identifiers = {c: Identifier(s.reduced.q0, s.protocol.harmonic)
                            for c, s in self.setups.items()}
        self.fitters = {c: MarkerSensor(s.protocol.sensor, s.reduced.q0)
                        for c, s in self.setups.items()}
        self.count = dict.fromkeys(self.setups, 0)
        self.checked = {c: BenchInputs(c, s.plan.load_limit_n) for c, s in self.setups.items()}
        self.results = {}
        self.unacked = {}
        self.ack_pub = self.advertise(KeyValue, ACK_TOPIC)
        self.results_pub = self.create_publisher(DiagnosticArray, RESULTS_TOPIC, latched_qos())
        self.series_pubs = {(c, q): self.create_publisher(
            Float64MultiArray, f"identification/{c}/{q}", latched_qos(1))
            for c in self.setups for q in IDENTIFIED_UNITS}
        for c in self.setups:
            join = SampleJoin("phase", ("load", "measured"), self._handler(c),
                              needs=lambda h: ("measured",) if is_end_marker(h)
                              else ("load", "measured"))
            self.subscribe(String, bench_topic(c, "phase"), join.callback("phase"), raw=True)
            self.subscribe(WrenchStamped, bench_topic(c, "load"), join.callback("load"),
                           raw=True)
            self.subscribe(PoseArray, bench_topic(c, "markers/measured"),
                           join.callback("measured"), raw=True)

    def _handler(self, component):
        identifier = self.identifiers[component]
        checked = self.checked[component]

        def handle(phase, inputs):
            ns, force = checked.load(inputs["load"]) if "load" in inputs else (None, 0.0)
            sample, end_ns = sample_from_phase(phase, force)
            if sample is not None:
                identifier.add_load(sample)
            settled = self._measurements(component, inputs["measured"])
            if sample is None:
                self._finish(component, end_ns)
                self._ack(end_ns, component, "done")
                return
            if settled or may_end_test(sample):  # the actuator waits for this one
                self._ack(ns, component, " ".join(["settled", *settled]) if settled else "")
            else:
                self.unacked[component] = ns
        return handle

    def _measurements(self, component, data):
        fitter, identifier = self.fitters[component], self.identifiers[component]
        n = len(fitter.offsets)
        stamp_ns, points = self.checked[component].markers("markers/measured", data)
        settled = []
        for chunk in np.split(points, len(points) // n) if len(points) else []:
            measurement = fitter.measurement(self.count[component], stamp_ns / 1e9, chunk)
            self.count[component] += 1
            done = identifier.add_measurement(measurement)
            if done:
                settled.append(done)
        return settled

    def _ack(self, ns, component, words):
        """/rig/ack value '<ns> <component> [settled <test>... | done]'."""
        value = f"{ns} {component} {words}".strip()
        self.ack_pub.publish(KeyValue(key=self.get_name(), value=value))
        self.unacked.pop(component, None)

    def acknowledge(self):
        """After a burst: acknowledge the samples nobody waits for, one ack per component."""
        for component, ns in list(self.unacked.items()):
            self._ack(ns, component, "")

    def _finish(self, component, end_ns):
        from motoflex_ros.identify.results import identify_component
        setup = self.setups[component]
        result = identify_component(component, self.identifiers[component].readings(),
                                    setup.modes, setup.reduced.q0)
        self.results[component] = result
        msg = DiagnosticArray(status=identification_statuses(component, result.to_dict()))
        msg.header.stamp = time_msg(end_ns)
        self.results_pub.publish(msg)
        for quantity, series in identified_series(result.to_dict()).items():
            self.series_pubs[component, quantity].publish(series)
        self.get_logger().info(f"{component}: identified, k = {result.static['k']:.6g} N m/rad")
        if not result.split_identifiable:
            self.get_logger().warning(f"{component}: k_t, k_b not identifiable: "
                                      f"{result.split.info['split_problem']}")
        if len(self.results) == len(self.setups):
            if self.params["result_file"]:
                write_results(self.params["result_file"],   # as ``motoflex identify --out``
                              {c: self.results[c].to_dict() for c in self.setups})
            self.finished = self.params["exit_when_done"]


def main(args=None):
    """Console script ``identification``."""
    return run_node(IdentificationNode, args)


if __name__ == "__main__":
    sys.exit(main())
