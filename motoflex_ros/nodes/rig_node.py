"""The base class of the rig's nodes: parameters, publishers and subscriptions, readiness.

:class:`RigNode` declares and validates the node's parameters (:mod:`.params`), turns on
``use_sim_time`` unless told otherwise, creates reliable keep-all publishers and subscriptions,
accepts messages only from its own run's publishers and counts lost messages per publisher
(:mod:`.endpoints`: a foreign publisher fails the run), and announces on ``/rig/ready`` once
every subscription sees a publisher and every publisher is matched with each subscriber the graph
knows on its topic (a reliable, volatile publisher drops what it sends before the match: a worker
whose reader matched only after the first window of samples went by stalled the run). A writer
whose participant has not yet discovered a reader still counts as matched, so the condition must
also have held for READY_HOLD_S: the two directions of discovery are milliseconds apart, and the
recorder's subscriptions, created when it discovers a topic, were matched by their writers a few
tens of samples late (the run's zero-loss check failed) without it.

The messages are taken, published and spun through :mod:`.transport`; every executable's
``main`` is :func:`.node_main.run_node`.
"""
import time

from diagnostic_msgs.msg import KeyValue
from rclpy.node import Node
from rclpy.parameter import Parameter
from std_msgs.msg import String

from motoflex_ros.nodes.endpoints import InputGuard, RunEndpoints
from motoflex_ros.nodes.interfaces import ACK_TOPIC, READY_TOPIC
from motoflex_ros.nodes.params import declare_parameters
from motoflex_ros.nodes.qos_profiles import latched_qos, reliable_qos
from motoflex_ros.nodes.transport import publisher_gid

__all__ = ["RigNode", "MATCH_TIMEOUT_S", "READY_HOLD_S", "GAP_EXIT_CODE"]

MATCH_TIMEOUT_S = 5.0  # longest wait for the publishers' side of discovery [s]
READY_HOLD_S = 0.3  # inputs must have been ready this long before /rig/ready [s]
GAP_EXIT_CODE = 3  # a node that saw a sequence gap exits with this code


class RigNode(Node):
    """Base of the rig's nodes. Subclasses set ``PARAMS`` (tuple of :class:`.params.Param`)
    and ``TOPICS`` (tuple of :class:`.interfaces.Topic`: what the node publishes and
    subscribes)."""

    PARAMS = ()
    TOPICS = ()

    NAME = "node"
    ENDS_ITSELF = False   # does the node finish on its own (``finished``)? see run_node
    SIM_TIME = True       # on /clock (use_sim_time) unless told otherwise; not the clock source

    def __init__(self, name=None):
        super().__init__(name or self.NAME)
        if self.SIM_TIME and "use_sim_time" not in self._parameter_overrides:
            self.set_parameters([Parameter("use_sim_time", value=True)])
        self.params = declare_parameters(self, self.PARAMS)
        self.finished = False
        self.exit_code = 0
        self._checked = set()
        self.guard = InputGuard(self, RunEndpoints.from_environment(self.get_name()),
                                count_gaps=self._checked.__contains__)
        self._ready_sent = False
        self._ready_since = None
        self._ready_pub = self.create_publisher(String, READY_TOPIC, latched_qos())
        self._ack_pub = None
        self._advertised = []
        self._match_deadline = time.monotonic() + MATCH_TIMEOUT_S
        self._processed_ns = None
        self._acked_ns = None

    def subscribe(self, msg_type, topic, callback, raw=False, qos=None, publishers=None):
        """Reliable keep-all subscription whose sequence numbers are checked for gaps; with
        ``publishers`` (node names) it accepts only those of the run's nodes."""
        sub = self.create_subscription(msg_type, topic, callback, qos or reliable_qos(),
                                       raw=raw)
        self._checked.add(sub)
        if publishers is not None:
            self.guard.only_from(sub, publishers)
        return sub

    def advertise(self, msg_type, topic, qos=None):
        """Reliable keep-all publisher."""
        publisher = self.create_publisher(msg_type, topic, qos or reliable_qos())
        self._advertised.append(publisher)
        return publisher

    def create_publisher(self, *args, **kwargs):
        """Node.create_publisher; the publisher is written down as one of the run's."""
        publisher = super().create_publisher(*args, **kwargs)
        guard = getattr(self, "guard", None)   # rclpy's own publishers come before it
        if guard is not None and guard.endpoints is not None:
            guard.endpoints.register(publisher, publisher_gid(publisher, self,
                                                              guard.endpoints.owners))
        return publisher

    @property
    def gaps(self):
        """Messages lost so far (over every publisher of every checked subscription)."""
        return self.guard.gaps

    def inputs_ready(self):
        """True when every checked subscription sees at least one publisher and every
        publisher of :meth:`advertise` is matched with every subscriber the graph knows on
        its topic (not waited for longer than MATCH_TIMEOUT_S after start)."""
        return all(sub.get_publisher_count() > 0 for sub in self._checked) and (
            time.monotonic() > self._match_deadline or self.publishers_matched(self._advertised))

    def publishers_matched(self, publishers):
        """True when each of ``publishers`` is matched with every subscriber the ROS graph
        knows on its topic (the writers' side of discovery is done for them)."""
        return all(pub.get_subscription_count() >= self.count_subscribers(pub.topic_name)
                   for pub in publishers)

    def announce_ready(self):
        """Publish this node's name on /rig/ready once its inputs see their publishers."""
        if self._ready_sent:
            return True
        if not self.inputs_ready():
            self._ready_since = None
        elif self._ready_since is None:
            self._ready_since = time.monotonic()
        elif time.monotonic() - self._ready_since >= READY_HOLD_S:
            self._ready_pub.publish(String(data=self.get_name()))
            self._ready_sent = True
        return self._ready_sent

    def processed(self, sim_time_ns):
        """Note that all up to ``sim_time_ns`` was handled (acknowledged after the burst)."""
        if self._ack_pub is None:
            self._ack_pub = self.advertise(KeyValue, ACK_TOPIC)
        self._processed_ns = sim_time_ns

    def acknowledge(self):
        """Publish on /rig/ack (key: node name, value: sim time [ns]) what was handled."""
        if self._processed_ns is not None and self._processed_ns != self._acked_ns:
            self._ack_pub.publish(KeyValue(key=self.get_name(), value=str(self._processed_ns)))
            self._acked_ns = self._processed_ns

    def step(self, spinner):
        """One turn of the main loop: wait for messages, handle them all, acknowledge."""
        self.announce_ready()
        spinner.spin_once(0.1)
        self.acknowledge()

    def close(self, reason):
        """Called once when the loop ends (``reason``: 'finished', 'SIGINT', 'SIGTERM')."""
        if self.gaps:
            self.get_logger().error(f"{self.gaps} message(s) lost in total")
            self.exit_code = self.exit_code or GAP_EXIT_CODE
