"""bag_replay: republishes a recorded bag, its /clock included, in recording order.

Topics go out relative to the node's namespace (a bag's /bench/x as /rig_a/bench/x under
/rig_a). Parameters: ``bag`` (directory), ``rate`` (0: as fast as the acknowledging nodes
allow; R > 0: R times the recorded speed), ``ack_from``/``wait_for``/``window``/
``stall_timeout`` as for sim_clock (window in seconds of simulated time), ``exclude`` topic
prefixes not to republish (default: the rig's own /rig/*; topics of a type this installation
has no Python messages for, the bag's tf2_msgs /tf and /tf_static, are not either). Messages
go out as the recorded CDR bytes, unchanged, on reliable keep-all publishers, so a node fed
from the replay sees exactly what it saw live.
"""
import sys
import time

from motoflex_ros.nodes.cdr import clock_ns_from_cdr
from motoflex_ros.nodes.interfaces import PACER_TOPICS, RELIABLE, RIG_TOPICS, Topic, message_class
from motoflex_ros.nodes.node_main import run_node
from motoflex_ros.nodes.pacing import AckGate, ReadyWatch
from motoflex_ros.nodes.params import Param, ParameterError
from motoflex_ros.nodes.rig_node import RigNode
from motoflex_ros.nodes.stamps import seconds_to_ns
from motoflex_ros.nodes.transport import publish_patiently
from motoflex_ros.record.mcap_bag import bag_info, read_messages
from motoflex_ros.units import NS_PER_S

__all__ = ["BagReplay", "main"]


class BagReplay(RigNode):
    """Publishes the messages of a bag, paced by acknowledgements or by the wall clock."""

    NAME = "bag_replay"
    ENDS_ITSELF = True
    PARAMS = (
        Param("bag", "", description="bag directory to replay"),
        Param("rate", 0.0, 0.0, 1000.0, description="replay speed (0: lock-step, fastest)"),
        Param("ack_from", (), description="nodes that acknowledge on /rig/ack"),
        Param("wait_for", (), description="nodes that must be ready before the first message"),
        Param("window", 0.05, 0.0, 1e6, description="simulated time ahead of the acks [s]"),
        Param("stall_timeout", 10.0, 0.1, 3600.0,
              description="max wait for an ack, or for a node to be ready [s]"),
        Param("exclude", ("/rig/",), description="topic prefixes not republished"),
    )
    TOPICS = RIG_TOPICS + PACER_TOPICS + (
        Topic("pub", "<each topic of the bag>", "the topic's type in the bag", RELIABLE,
              "the bag's messages in recorded order, /clock with them (not those under "
              "exclude; /tf, /tf_static only where tf2_msgs has Python messages)",
              when="from the bag"),
    )

    def __init__(self):
        super().__init__()
        p = self.params
        if not p["bag"]:
            raise ParameterError("node 'bag_replay': parameter 'bag' is required")
        self.info = bag_info(p["bag"])
        skip = tuple(p["exclude"])
        self.pubs = {}
        for t in self.info.topics:
            if t.name.startswith(skip):
                continue
            try:
                self.pubs[t.name] = self.advertise(message_class(t.type), t.name.lstrip("/"))
            except ImportError:   # tf2_msgs (the bag's /tf): no wheel for rclpy here
                self.get_logger().info(f"{t.name} not republished: no Python messages of "
                                       f"{t.type} in this installation")
        self.messages = (m for m in read_messages(p["bag"], topics=list(self.pubs)))
        self.ready = ReadyWatch(self, set(p["wait_for"]) | set(p["ack_from"]),
                                self.pubs.values(), p["stall_timeout"])
        self.gate = AckGate(self, p["ack_from"], seconds_to_ns(p["window"]),
                            p["stall_timeout"])
        self.pending = None
        self.last_clock_ns = -1
        self.started = None
        self.published = 0

    def step(self, spinner):
        """Wait for the graph, then publish while the gate and the rate allow."""
        if self.started is None:
            spinner.spin_once(0.05)
            if self.ready.ready():
                self.started = time.monotonic()
                self.gate.touch()
            return
        if self._publish_allowed():
            return
        if self.pending is None and self.gate.all_acked(self.last_clock_ns):
            self.finished = True
            self.get_logger().info(f"replayed {self.published} messages")
            return
        if spinner.spin_once(0.5) == 0:
            self.gate.check_stall()

    def _publish_allowed(self):
        """Publish messages until one must wait; True if the rate asks for a sleep."""
        while True:
            if self.pending is None:
                self.pending = next(self.messages, None)
                if self.pending is None:
                    return False
            msg = self.pending
            if msg.topic == "/clock":
                t_ns = clock_ns_from_cdr(msg.data)
                if not self.gate.allows(t_ns):
                    return False
                self.last_clock_ns = t_ns
            if self._sleep_for_rate(msg.log_time_ns):
                return True
            publish_patiently(self.pubs[msg.topic], msg.data, self.params["stall_timeout"])
            self.published += 1
            self.pending = None

    def _sleep_for_rate(self, log_time_ns):
        rate = self.params["rate"]
        if rate <= 0:
            return False
        due = self.started + (log_time_ns - self.info.start_ns) / NS_PER_S / rate
        wait = due - time.monotonic()
        if wait > 0:
            time.sleep(min(wait, 0.05))
            return True
        return False


def main(args=None):
    """Console script ``bag_replay``."""
    return run_node(BagReplay, args)


if __name__ == "__main__":
    sys.exit(main())
