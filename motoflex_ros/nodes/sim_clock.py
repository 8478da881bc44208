"""sim_clock: the clock source of a run. Publishes /clock (rosgraph_msgs/Clock) step by step.

Parameters: ``dt`` [s] step of simulated time, ``duration`` [s] end of the run, ``window``
[steps] how far ahead of the slowest acknowledging node time may run, ``ack_from`` nodes that
acknowledge on /rig/ack, ``wait_for`` nodes that must be ready before the first tick,
``stall_timeout`` [s]. The node exits 0 when every acknowledging node has handled the last
step, and 2 (naming the node) when one stops acknowledging.
"""
import sys

from rosgraph_msgs.msg import Clock

from motoflex_ros.nodes.interfaces import PACER_TOPICS, READY, RELIABLE, Topic
from motoflex_ros.nodes.node_main import run_node
from motoflex_ros.nodes.pacing import AckGate, ReadyWatch
from motoflex_ros.nodes.params import Param
from motoflex_ros.nodes.rig_node import RigNode
from motoflex_ros.nodes.stamps import clock_msg, seconds_to_ns

__all__ = ["SimClock", "main"]


class SimClock(RigNode):
    """Publishes /clock at k * dt for k = 0..duration/dt, paced by acknowledgements."""

    NAME = "sim_clock"
    ENDS_ITSELF = True
    # The clock source runs on wall time: with use_sim_time its own time source subscribes to
    # /clock, and "a subscriber of /clock" counted that one, so a sim_clock started alone
    # published its whole run to itself and ended (seen as a node that exits at start-up).
    SIM_TIME = False
    PARAMS = (
        Param("dt", 0.001, 1e-6, 1.0, description="step of simulated time [s]"),
        Param("duration", 1.0, 0.0, 1e6, description="simulated time of the run [s]"),
        Param("window", 64, 1, 1_000_000, description="steps ahead of the slowest ack [-]"),
        Param("ack_from", (), description="nodes that acknowledge on /rig/ack"),
        Param("wait_for", (), description="nodes that must be ready before the first step"),
        Param("stall_timeout", 10.0, 0.1, 3600.0,
              description="max wait for an ack, or for a node to be ready [s]"),
    )
    TOPICS = (READY, *PACER_TOPICS, Topic("pub", "clock", "rosgraph_msgs/msg/Clock", RELIABLE,
                                          "simulated time k * dt, paced by the acks"))

    def __init__(self):
        super().__init__()
        p = self.params
        self.dt_ns = seconds_to_ns(p["dt"])
        self.steps = int(round(p["duration"] / p["dt"]))
        self.end_ns = self.steps * self.dt_ns
        self.clock_pub = self.advertise(Clock, "clock")
        self.ready = ReadyWatch(self, set(p["wait_for"]) | set(p["ack_from"]), [self.clock_pub],
                                p["stall_timeout"])
        self.gate = AckGate(self, p["ack_from"], p["window"] * self.dt_ns, p["stall_timeout"])
        self.k = None

    def step(self, spinner):
        """Wait for the graph, then publish as many steps as the window allows."""
        if self.k is None:
            spinner.spin_once(0.05)
            if not self.ready.ready():
                return
            if self.clock_pub.get_subscription_count() > 0:
                self.k = 0
                self.gate.touch()
            else:
                self.ready.waiting.still("a subscriber of /clock")
            return
        while self.k <= self.steps and self.gate.allows(self.k * self.dt_ns):
            self.clock_pub.publish(clock_msg(self.k * self.dt_ns))
            self.k += 1
        if self.k > self.steps and self.gate.all_acked(self.end_ns):
            self.finished = True
            return
        if spinner.spin_once(0.5) == 0:
            self.gate.check_stall()


def main(args=None):
    """Console script ``sim_clock``."""
    return run_node(SimClock, args)


if __name__ == "__main__":
    sys.exit(main())
