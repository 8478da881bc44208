"""identification: identifies each component's lumped models from loads and measured poses.

``mode: virtual`` (:mod:`.virtual_identification`): per sample it pairs the phase and load
(/bench/<c>/phase, /load) with what the sensor delivered (/bench/<c>/markers/measured), feeds
the core's rigid fit and streaming Identifier, then acknowledges the sample on /rig/ack
(adding 'settled <test>' when a harmonic test's mean has settled, so the actuator ends that
test). At a component's end marker it computes l, beta, b, k, c, J, k_t, k_b (core
identify_component), publishes them on /identification/results
(diagnostic_msgs/DiagnosticArray, one status per test, KeyValue values), the same k [N m/rad],
l [m] and beta [rad] of the static, torsion and bending models as numbers a plot panel draws
on /identification/<c>/{k, l, beta} (std_msgs/Float64MultiArray, latched) and, once every
component is done, writes ``result_file`` atomically; each component's entry says which files
it came from ("inputs": {absolute path: SHA-256} of what its setup read, held to the run's
pins). Loads and measured markers that are not finite, loads beyond the protocol's range and
stamps that go back stop the node at that message (:mod:`.message_checks`), before the core
sees it.

``mode: measured`` (:mod:`.measured_identification`): a real rig's topics, no FE model, no
lock-step; identifies what arrived when asked.
"""
import sys
from dataclasses import replace

from diagnostic_msgs.msg import DiagnosticArray

from motoflex_ros.nodes.bench_graph import BENCH_PARAMS
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
from motoflex_ros.nodes.measured_identification import MEASURED_TOPICS, MeasuredIdentification
from motoflex_ros.nodes.measured_inputs import MEASURED_PARAMS
from motoflex_ros.nodes.node_main import run_node
from motoflex_ros.nodes.params import Param
from motoflex_ros.nodes.qos_profiles import latched_qos
from motoflex_ros.nodes.rig_node import RigNode
from motoflex_ros.nodes.virtual_identification import VirtualIdentification

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
    ) + MEASURED_TOPICS

    def __init__(self):
        self.mode = None
        super().__init__()
        self.results_pub = self.create_publisher(DiagnosticArray, RESULTS_TOPIC, latched_qos())
        self.ENDS_ITSELF = self.params["exit_when_done"]   # a job to finish: replay --identify
        measured = self.params["mode"] == "measured"
        self.mode = (MeasuredIdentification if measured else VirtualIdentification)(
            self, self.params)

    def inputs_ready(self):
        """Measured mode: the rig's topics have publishers (then /rig/ready goes out)."""
        if isinstance(self.mode, MeasuredIdentification):
            return self.mode.inputs_ready()
        return super().inputs_ready()

    def step(self, spinner):
        """One turn of the main loop (measured mode: identify once asked)."""
        if isinstance(self.mode, VirtualIdentification):
            return super().step(spinner)
        self.announce_ready()
        self.mode.step(spinner)

    def acknowledge(self):
        """Virtual mode, after a burst: the samples nobody waits for."""
        if isinstance(self.mode, VirtualIdentification):
            self.mode.acknowledge()


def main(args=None):
    """Console script ``identification``."""
    return run_node(IdentificationNode, args)


if __name__ == "__main__":
    sys.exit(main())
