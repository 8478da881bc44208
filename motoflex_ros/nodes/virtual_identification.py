"""The identification node's ``mode: virtual``: the emulated bench's components, in lock-step.

:class:`VirtualIdentification` subscribes per component to the phase, the load and the measured
markers, joins them per sample (:class:`.bench_graph.SampleJoin`), acknowledges each sample on
/rig/ack once handled and, at a component's end marker, publishes its identification
(/identification/results, /identification/<c>/{k, l, beta}) and, when every component is
done, writes ``result_file``. :class:`ComponentStream` is one component's part: the
load sample goes to the core's streaming :class:`motoflex_ros.identify.identifier.Identifier`,
each delivered marker set is refitted to a pose (core :class:`motoflex_ros.bench.sensor.
MarkerSensor`) and goes there too. :meth:`ComponentStream.take` says what the node must
acknowledge; at the component's end marker :meth:`ComponentStream.result` computes l, beta,
b, k, c, J, k_t, k_b (core :func:`motoflex_ros.identify.results.identify_component`).
"""
import numpy as np
from diagnostic_msgs.msg import DiagnosticArray, KeyValue
from geometry_msgs.msg import PoseArray, WrenchStamped
from std_msgs.msg import Float64MultiArray, String

from motoflex_ros.bench.sensor import MarkerSensor
from motoflex_ros.formats.json_yaml import write_results
from motoflex_ros.identify.identifier import Identifier
from motoflex_ros.identify.results import identify_component
from motoflex_ros.nodes.bench_graph import SampleJoin, campaign_setups
from motoflex_ros.nodes.bench_graph import topic as bench_topic
from motoflex_ros.nodes.cdr import is_end_marker, sample_from_phase
from motoflex_ros.nodes.interfaces import ACK_TOPIC
from motoflex_ros.nodes.load_actuator import may_end_test
from motoflex_ros.nodes.message_checks import BenchInputs
from motoflex_ros.nodes.qos_profiles import latched_qos
from motoflex_ros.nodes.result_messages import (
    IDENTIFIED_UNITS,
    identification_statuses,
    identified_series,
)
from motoflex_ros.nodes.stamps import time_msg
from motoflex_ros.units import NS_PER_S

__all__ = ["VirtualIdentification", "ComponentStream", "DONE"]

DONE = "done"   # the acknowledgement of a component's end marker


class ComponentStream:
    """A component's identification fed sample by sample (``setup``: its CampaignSetup;
    ``checked``: its :class:`.message_checks.BenchInputs`)."""

    def __init__(self, component, setup, checked):
        self.component = component
        self.setup = setup
        self.checked = checked
        self.identifier = Identifier(setup.reduced.q0, setup.protocol.harmonic)
        self.fitter = MarkerSensor(setup.protocol.sensor, setup.reduced.q0)
        self.count = 0

    def take(self, phase, inputs):
        """Feed one joined sample (``inputs``: 'load' and 'measured' CDR bytes); returns
        (stamp [ns], what to acknowledge): :data:`DONE` at the end marker, 'settled <test>...'
        when a harmonic test's mean settled, '' when the actuator waits for this sample, None
        when nobody waits for it (acknowledged with the burst)."""
        ns, load = self.checked.wrench(inputs["load"]) if "load" in inputs else (None, 0.0)
        sample, end_ns = sample_from_phase(phase, load)
        if sample is not None:
            self.identifier.add_load(sample)
        settled = self._measurements(inputs["measured"])
        if sample is None:
            return end_ns, DONE
        if settled:
            return ns, " ".join(["settled", *settled])
        return ns, "" if may_end_test(sample) else None

    def _measurements(self, data):
        """Refit each delivered marker set and feed it; the tests whose mean settled."""
        n = len(self.fitter.offsets)
        stamp_ns, points = self.checked.markers("markers/measured", data)
        settled = []
        for chunk in np.split(points, len(points) // n) if len(points) else []:
            measurement = self.fitter.measurement(self.count, stamp_ns / NS_PER_S, chunk)
            self.count += 1
            done = self.identifier.add_measurement(measurement)
            if done:
                settled.append(done)
        return settled

    def result(self):
        """The component's ComponentIdentification from everything fed so far."""
        setup = self.setup
        return identify_component(self.component, self.identifier.readings(), setup.modes,
                                  setup.reduced.q0, setup.carried)


class VirtualIdentification:
    """The virtual mode of ``node`` (an identification node with ``results_pub``)."""

    def __init__(self, node, params):
        self.node = node
        self.params = params
        self.inputs = {}
        setups = campaign_setups(params, self.inputs)
        self.streams = {c: ComponentStream(c, s, BenchInputs.of_plan(c, s.plan,
                                                                     node.get_namespace()))
                        for c, s in setups.items()}
        self.results = {}
        self.unacked = {}
        self.ack_pub = node.advertise(KeyValue, ACK_TOPIC)
        self.series_pubs = {(c, q): node.create_publisher(
            Float64MultiArray, f"identification/{c}/{q}", latched_qos(1))
            for c in setups for q in IDENTIFIED_UNITS}
        for c in setups:
            join = SampleJoin("phase", ("load", "measured"), self._handler(c),
                              needs=lambda h: ("measured",) if is_end_marker(h)
                              else ("load", "measured"))
            node.subscribe(String, bench_topic(c, "phase"), join.callback("phase"), raw=True)
            node.subscribe(WrenchStamped, bench_topic(c, "load"), join.callback("load"),
                           raw=True)
            node.subscribe(PoseArray, bench_topic(c, "markers/measured"),
                           join.callback("measured"), raw=True)

    def _handler(self, component):
        stream = self.streams[component]

        def handle(phase, inputs):
            ns, words = stream.take(phase, inputs)
            if words == DONE:
                self._finish(component, ns)
            if words is None:   # nobody waits for this one: acknowledged after the burst
                self.unacked[component] = ns
            else:
                self._ack(ns, component, words)
        return handle

    def _ack(self, ns, component, words):
        """/rig/ack value '<ns> <component> [settled <test>... | done]'."""
        value = f"{ns} {component} {words}".strip()
        self.ack_pub.publish(KeyValue(key=self.node.get_name(), value=value))
        self.unacked.pop(component, None)

    def acknowledge(self):
        """After a burst: acknowledge the samples nobody waits for, one ack per component."""
        for component, ns in list(self.unacked.items()):
            self._ack(ns, component, "")

    def _finish(self, component, end_ns):
        result = self.results[component] = self.streams[component].result()
        msg = DiagnosticArray(status=identification_statuses(component, result.to_dict()))
        msg.header.stamp = time_msg(end_ns)
        self.node.results_pub.publish(msg)
        for quantity, series in identified_series(result.to_dict()).items():
            self.series_pubs[component, quantity].publish(series)
        log = self.node.get_logger()
        log.info(f"{component}: identified, k = {result.static['k']:.6g} N m/rad")
        if not result.split_identifiable:
            log.warning(f"{component}: k_t, k_b not identifiable: "
                        f"{result.split.info['split_problem']}")
        if len(self.results) == len(self.streams):
            if self.params["result_file"]:
                # as ``motoflex identify --out``, with the hashes of the files each came from
                write_results(self.params["result_file"],
                              {c: {**self.results[c].to_dict(), "inputs": self.inputs[c]}
                               for c in self.streams})
            self.node.finished = self.params["exit_when_done"]
