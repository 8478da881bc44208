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
``result_file`` atomically; each component's entry says which files it came from ("inputs":
{absolute path: SHA-256} of what its setup read, held to the run's pins).
Loads and measured markers that are not finite, loads beyond the protocol's range and stamps
that go back stop the node at that message (:mod:`.message_checks`), before the core sees it.

``mode: measured`` (issue 17): a real rig, no FE model, no lock-step. The node reads the
bench file (``bench_file``), subscribes to the load cell (geometry_msgs/WrenchStamped,
``load_topic``) and the markers (``markers_topic``: one geometry_msgs/PoseArray per frame, or
with ``marker_msg`` PointStamped / PoseStamped one topic ``<markers_topic>/m<i>`` per marker),
keeps every message as it comes (asynchronous: any order across topics, any rates) and
acknowledges nothing. A message on ``identify_topic`` (std_msgs/Empty), or ``idle_timeout_s``
without input, identifies what has arrived (header stamps, the core's approximate-time
matching, :func:`motoflex_ros.identify.measured.identify_measured`), publishes it on
identification/results and writes ``result_file``. Topic names default to
bench/<bench>/{load, markers/measured, identify} (relative: in the node's namespace) and can
be set or remapped (``-r``).
"""
import sys
from dataclasses import replace

import numpy as np
from diagnostic_msgs.msg import DiagnosticArray, KeyValue
from geometry_msgs.msg import PoseArray, WrenchStamped
from std_msgs.msg import Float64MultiArray, String

from motoflex_ros.errors import MotoflexError
from motoflex_ros.nodes.bench_graph import BENCH_PARAMS, SampleJoin, campaign_setups
from motoflex_ros.nodes.bench_graph import topic as bench_topic
from motoflex_ros.nodes.cdr import is_end_marker, sample_from_phase
from motoflex_ros.nodes.interfaces import (
    ACK_OUT,
    LATCHED,
    LATCHED_LAST,
    LOAD_IN,
    PHASE_IN,
    RELIABLE,
    RIG_TOPICS,
    Topic,
)
from motoflex_ros.nodes.load_actuator import may_end_test
from motoflex_ros.nodes.measured_inputs import MEASURED_PARAMS, MeasuredInputs
from motoflex_ros.nodes.message_checks import BenchInputs
from motoflex_ros.nodes.params import Param
from motoflex_ros.nodes.result_messages import (
    IDENTIFIED_UNITS,
    identification_statuses,
    identified_series,
)
from motoflex_ros.nodes.runtime import ACK_TOPIC, RigNode, latched_qos, run_node
from motoflex_ros.nodes.stamps import time_msg
from motoflex_ros.results_file import write_results

__all__ = ["IdentificationNode", "main", "RESULTS_TOPIC"]

RESULTS_TOPIC = "identification/results"


class IdentificationNode(RigNode):
    """Loads and measurements in, identified models out."""

    NAME = "identification"
    PARAMS = BENCH_PARAMS + (
        Param("result_file", "", description="JSON file of the results ('': none)"),
        Param("exit_when_done", False, description="exit once every component is identified"),
        Param("mode", "virtual", choices=("virtual", "measured"),
              description="virtual: the emulated bench in lock-step; measured: a real rig's "
                          "topics, no FE model"),
    ) + MEASURED_PARAMS
    TOPICS = RIG_TOPICS + (
        Topic("pub", RESULTS_TOPIC, "diagnostic_msgs/msg/DiagnosticArray", LATCHED,
              "identified l, beta, b, k, c, J, k_t, k_b (one status per component, KeyValue "
              "pairs), as each component ends"),
        Topic("pub", "identification/{c}/l", "std_msgs/msg/Float64MultiArray", LATCHED_LAST,
              "the identified joint distance l [m] of each estimate"),
        Topic("pub", "identification/{c}/beta", "std_msgs/msg/Float64MultiArray",
              LATCHED_LAST, "the identified axis angle beta [rad] of each estimate"),
        Topic("pub", "identification/{c}/k", "std_msgs/msg/Float64MultiArray", LATCHED_LAST,
              "the identified stiffness k [N m/rad] of each estimate"),
        replace(PHASE_IN, when="mode virtual"), replace(LOAD_IN, when="mode virtual"),
        Topic("sub", "bench/{c}/markers/measured", "geometry_msgs/msg/PoseArray", RELIABLE,
              "measured marker positions [m]", when="mode virtual"),
        replace(ACK_OUT, when="mode virtual"),
        Topic("sub", "bench/<bench>/load (load_topic)", "geometry_msgs/msg/WrenchStamped",
              "best effort or reliable (qos), keep all", "the load cell", when="mode measured"),
        Topic("sub", "bench/<bench>/markers/measured (markers_topic)",
              "geometry_msgs/msg/PoseArray (or per marker .../m1, /m2, ...: PointStamped or "
              "PoseStamped, marker_msg)", "best effort or reliable (qos), keep all",
              "the markers", when="mode measured"),
        Topic("sub", "bench/<bench>/identify (identify_topic)", "std_msgs/msg/Empty",
              "reliable, last 10", "identify what arrived so far", when="mode measured"),
    )

    def __init__(self):
        self.live = None
        super().__init__()
        self.results_pub = self.create_publisher(DiagnosticArray, RESULTS_TOPIC, latched_qos())
        if self.params["mode"] == "measured":
            self.live = MeasuredInputs(self, self.params)
            self.ENDS_ITSELF = self.params["exit_when_done"]
            return
        self._init_virtual()

    def inputs_ready(self):
        """Measured mode: the rig's topics have publishers (then /rig/ready goes out)."""
        if self.live is None:
            return super().inputs_ready()
        return self.live.inputs_ready()

    def step(self, spinner):
        """One turn: in measured mode, identify once asked (after draining what arrived)."""
        if self.live is None:
            return super().step(spinner)
        self.announce_ready()
        spinner.spin_once(0.1)
        if self.live.due():
            spinner.spin_once(0)   # what arrived with the request: every topic drained
            try:
                self._finish_measured()
            except MotoflexError as exc:   # a live rig may still send what is missing
                if self.params["exit_when_done"]:
                    raise
                self.get_logger().error(f"not identified yet: {exc}")

    def _finish_measured(self):
        from motoflex_ros.identify.measured import identify_measured
        from motoflex_ros.results_file import to_jsonable
        bench = self.live.bench
        result = identify_measured(self.live.measurements(), bench).to_dict()
        measured = result.pop("measured")
        summary = {"frames": measured["frames"], **measured["counts"],
                   "reference": measured["reference"], "messages": dict(self.live.received)}
        result_dict = to_jsonable({**result, "measured": summary})
        msg = DiagnosticArray(status=identification_statuses(bench.name, result_dict))
        msg.header.stamp = self.get_clock().now().to_msg()
        self.results_pub.publish(msg)
        c = measured["counts"]
        self.get_logger().info(
            f"{bench.name}: identified from {measured['frames']} frames, k = "
            f"{result['static']['k']:.6g} N m/rad; dropped {c['dropped_marker_frames']} "
            f"marker frames, {c['dropped_load_samples']} load samples, unmatched "
            f"{c['unmatched_frames']}")
        if self.params["result_file"]:
            write_results(self.params["result_file"], {bench.name: {**result,
                                                                    "measured": measured}})
        self.finished = self.params["exit_when_done"]

    def _init_virtual(self):
        from motoflex_ros.bench.sensor import MarkerSensor
        from motoflex_ros.identify.identifier import Identifier
        self.inputs = {}
        self.setups = campaign_setups(self.params, self.inputs)
        self.ENDS_ITSELF = self.params["exit_when_done"]   # a job to finish: replay --identify
        self.identifiers = {c: Identifier(s.reduced.q0, s.protocol.harmonic)
                            for c, s in self.setups.items()}
        self.fitters = {c: MarkerSensor(s.protocol.sensor, s.reduced.q0)
                        for c, s in self.setups.items()}
        self.count = dict.fromkeys(self.setups, 0)
        self.checked = {c: BenchInputs.of_plan(c, s.plan, self.get_namespace())
                        for c, s in self.setups.items()}
        self.results = {}
        self.unacked = {}
        self.ack_pub = self.advertise(KeyValue, ACK_TOPIC)
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
            ns, load = checked.wrench(inputs["load"]) if "load" in inputs else (None, 0.0)
            sample, end_ns = sample_from_phase(phase, load)
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
        if self.live is not None:
            return
        for component, ns in list(self.unacked.items()):
            self._ack(ns, component, "")

    def _finish(self, component, end_ns):
        from motoflex_ros.identify.results import identify_component
        setup = self.setups[component]
        result = identify_component(component, self.identifiers[component].readings(),
                                    setup.modes, setup.reduced.q0, setup.carried)
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
                # as ``motoflex identify --out``, with the hashes of the files each came from
                write_results(self.params["result_file"],
                              {c: {**self.results[c].to_dict(), "inputs": self.inputs[c]}
                               for c in self.setups})
            self.finished = self.params["exit_when_done"]


def main(args=None):
    """Console script ``identification``."""
    return run_node(IdentificationNode, args)


if __name__ == "__main__":
    sys.exit(main())
