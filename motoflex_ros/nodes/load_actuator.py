"""load_actuator: plays each component's bench protocol and paces the whole bench graph.

Per sample of a component it publishes the phase (/bench/<c>/phase: the sample's test, kind,
phase and timing as JSON; the same as numbers a plot panel draws on /bench/<c>/phase_values,
:func:`motoflex_ros.nodes.rig_markers.phase_values_msg`) and the commanded load
(/bench/<c>/load, geometry_msgs/WrenchStamped, F_y at the loaded end). The identification node
acknowledges every sample on /rig/ack and may
answer 'settled <test>', which ends a harmonic test before the next sample, exactly as the
offline campaign does. Only a sample in the steady phase of a harmonic or sweep test can end
its own test that way (the identifier's running mean only moves there; a late answer about a
test that is over changes nothing), so after such a sample the actuator waits for its
acknowledgement (lock-step); other samples stream ahead, at most ``window`` unacknowledged.
The components run one after the other on one simulated clock, in the order of
``components`` (the run's time base, docs/virtual-bench.md): the first from t = 0, each
next one ``PAUSE_S`` after the previous one's last sample, its header stamps shifted by that
start (the phase JSON keeps the component's own t, which the identification reads). The next
component starts streaming as soon as the previous one's end marker is out, so the pipeline
stays full. /clock (every ``clock_period`` of simulated time, as a bag player does) is the
earliest sample time still in flight, so it never goes back.
"""
import sys
import time
from collections import deque

from diagnostic_msgs.msg import KeyValue
from geometry_msgs.msg import WrenchStamped
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import JointState
from std_msgs.msg import String

from motoflex_ros.bench.actuator import PAUSE_S, LoadActuator
from motoflex_ros.nodes.bench_graph import BENCH_PARAMS, campaign_setups, frame_id, topic
from motoflex_ros.nodes.cdr import phase_cdr, wrench_cdr
from motoflex_ros.nodes.interfaces import (
    ACK_TOPIC,
    PACER_TOPICS,
    PROGRESS_TOPIC,
    RELIABLE,
    RIG_TOPICS,
    Topic,
)
from motoflex_ros.nodes.node_main import run_node
from motoflex_ros.nodes.pacing import ReadyWatch, StallError
from motoflex_ros.nodes.params import Param
from motoflex_ros.nodes.rig_markers import PHASE_CODES, PHASE_VALUE_NAMES, phase_values_msg
from motoflex_ros.nodes.rig_node import RigNode
from motoflex_ros.nodes.stamps import clock_msg, seconds_to_ns

__all__ = ["LoadActuatorNode", "main", "may_end_test"]


def may_end_test(sample):
    """Can the identifier's answer to this sample end its test (steady harmonic/sweep)?"""
    return sample.kind in ("harmonic", "sweep") and sample.phase == "steady"


class LoadActuatorNode(RigNode):
    """Drives the bench: per component, one sample out, one acknowledgement back."""

    NAME = "load_actuator"
    ENDS_ITSELF = True
    PARAMS = BENCH_PARAMS + (
        Param("ack_from", "identification", description="node whose ack paces the run"),
        Param("wait_for", (), description="nodes that must be ready before the first sample"),
        Param("stall_timeout", 30.0, 0.1, 3600.0,
              description="max wait for an ack, or for a node to be ready [s]"),
        Param("window", 256, 1, 100_000, description="max unacknowledged samples [-]"),
        Param("clock_period", 0.01, 0.0, 1.0, description="/clock every so much sim time [s]"),
    )
    TOPICS = RIG_TOPICS + PACER_TOPICS + (
        Topic("pub", "clock", "rosgraph_msgs/msg/Clock", RELIABLE,
              "simulated time: the earliest sample not yet acknowledged, every clock_period"),
        Topic("pub", "bench/{c}/load", "geometry_msgs/msg/WrenchStamped", RELIABLE,
              "commanded load at the loaded end (force.y = F_y [N]; the moment tests' "
              "torque [N m]), frame <c>_clamp, stamped with the sample's simulated time"),
        Topic("pub", "bench/{c}/phase", "std_msgs/msg/String", RELIABLE,
              "the sample's test, kind, phase and timing as JSON; {\"end_ns\": ...} ends the "
              "component's campaign"),
        Topic("pub", "bench/{c}/phase_values", "sensor_msgs/msg/JointState", RELIABLE,
              f"the sample's phase as numbers, name {PHASE_VALUE_NAMES}: test number "
              f"(1-based), phase code {PHASE_CODES}, frequency [Hz], load amplitude [N or N m]; "
              "stamped like the load"),
        Topic("pub", "rig/progress", "diagnostic_msgs/msg/KeyValue", RELIABLE,
              "bench tests finished (key: component, value: count), for progress bars"),
    )

    def __init__(self):
        super().__init__()
        p = self.params
        self.setups = campaign_setups(p)
        self.actuators = {c: LoadActuator(s.plan) for c, s in self.setups.items()}
        self.clock_pub = self.advertise(Clock, "clock")
        self.load_pubs = {c: self.advertise(WrenchStamped, topic(c, "load")) for c in self.setups}
        self.phase_pubs = {c: self.advertise(String, topic(c, "phase")) for c in self.setups}
        self.value_pubs = {c: self.advertise(JointState, topic(c, "phase_values"))
                           for c in self.setups}
        self.ready = ReadyWatch(self, set(p["wait_for"]) | {p["ack_from"]},
                                [self.clock_pub, *self.load_pubs.values(),
                                 *self.phase_pubs.values()], p["stall_timeout"])
        self.subscribe(KeyValue, ACK_TOPIC, self._on_ack)
        # tests begun per component: the campaign's progress bar counts finished tests
        self.progress_pub = self.advertise(KeyValue, PROGRESS_TOPIC)
        self.tests_begun = dict.fromkeys(self.setups, 0)
        self.pending = {c: deque() for c in self.setups}  # ns awaiting their ack
        self.blocked = dict.fromkeys(self.setups, False)  # waiting for a steady sample's ack
        self.last_ns = dict.fromkeys(self.setups, -1)
        self.start_ns = dict.fromkeys(self.setups, 0)   # each component's start on the clock
        self.done = set()
        self.ended = set()
        self.clock_ns = -seconds_to_ns(p["clock_period"]) - 1  # the first tick is at t = 0
        self.started = False
        self.progress = time.monotonic()

    def _on_ack(self, msg):
        if msg.key != self.params["ack_from"]:
            return
        ns, component, *words = msg.value.split()
        pending = self.pending.get(component)
        if not pending or int(ns) < pending[0]:
            return
        while pending and pending[0] <= int(ns):
            pending.popleft()
        if not pending:
            self.blocked[component] = False
        self.progress = time.monotonic()
        if words and words[0] == "settled":
            for test in words[1:]:
                self.actuators[component].end_test(test)
        elif words == ["done"]:
            self.done.add(component)

    def step(self, spinner):
        """Wait for the graph; then send every component whose last sample was acknowledged."""
        if not self.started:
            spinner.spin_once(0.05)
            self.started = self.ready.ready()
            self.progress = time.monotonic()
            return
        if len(self.done) == len(self.setups):
            self.finished = True
            return
        outgoing = []
        c = self._streaming()
        while (c is not None and not self.blocked[c]
               and len(self.pending[c]) < self.params["window"]):
            outgoing.append(self._next(c))
            c = self._streaming()
        self._advance_clock()
        for publish in outgoing:
            publish()
        if spinner.spin_once(1.0) == 0 and time.monotonic() - self.progress > \
                self.params["stall_timeout"]:
            late = ", ".join(c for c, ns in self.pending.items() if ns)
            raise StallError(f"no acknowledgement from '{self.params['ack_from']}' for "
                             f"{self.params['stall_timeout']:g} s (components {late})")

    def _streaming(self):
        """The component whose samples go out now: the first one not ended; the next one
        starts PAUSE_S after the previous one's last sample (None when all have ended)."""
        previous = None
        for c in self.setups:
            if c not in self.ended:
                if self.last_ns[c] < 0 and previous is not None:
                    self.start_ns[c] = self.last_ns[previous] + seconds_to_ns(PAUSE_S)
                return c
            previous = c
        return None

    def _advance_clock(self):
        in_flight = [ns[0] for ns in self.pending.values() if ns]
        period = seconds_to_ns(self.params["clock_period"])
        if in_flight and min(in_flight) >= self.clock_ns + max(period, 1):
            self.clock_ns = min(in_flight)
            self.clock_pub.publish(clock_msg(self.clock_ns))

    def _next(self, component):
        """Take the component's next sample; returns the function that publishes it."""
        sample = self.actuators[component].next_sample()
        if sample is None:
            ns = self.last_ns[component] + 1
            self.pending[component].append(ns)
            self.last_ns[component] = ns
            self.ended.add(component)

            def publish_end():
                self.phase_pubs[component].publish(phase_cdr(end_ns=ns))
                self._publish_progress(component, self.tests_begun[component])
            return publish_end
        ns = self.start_ns[component] + seconds_to_ns(sample.t)
        self.pending[component].append(ns)
        self.last_ns[component] = ns
        self.blocked[component] = may_end_test(sample)
        self.tests_begun[component] += sample.test_start
        finished = self.tests_begun[component] - 1 if sample.test_start else None
        values = phase_values_msg(ns, self.tests_begun[component], sample)

        def publish():
            self.phase_pubs[component].publish(phase_cdr(sample))  # CDR bytes, no message objects
            self.load_pubs[component].publish(wrench_cdr(ns, frame_id(component),
                                                         sample.wrench_vector))
            self.value_pubs[component].publish(values)
            if finished is not None:
                self._publish_progress(component, finished)
        return publish

    def _publish_progress(self, component, finished):
        self.progress_pub.publish(KeyValue(key=component, value=str(finished)))


def main(args=None):
    """Console script ``load_actuator``."""
    return run_node(LoadActuatorNode, args)


if __name__ == "__main__":
    sys.exit(main())
