"""Lock-step pacing: a source publishes simulated time only as far as its consumers allow.

Consumers acknowledge on /rig/ack (diagnostic_msgs/KeyValue: key = node name, value = simulated
time [ns] they have fully handled, optionally followed by words for the source) after each
burst of messages. A pacing source
(:mod:`.sim_clock`, :mod:`.bag_replay`) lets simulated time run at most ``window_ns`` ahead of
the slowest acknowledgement. With reliable keep-all QoS nothing is dropped, the queues stay
bounded, and since every node handles its inputs in order the results do not depend on how fast
the machine is. Start-up: the source waits until every node it needs has announced itself on
/rig/ready (its subscriptions see their publishers), saying what it waits for every
WAIT_LOG_PERIOD_S and giving up after its stall timeout without progress (:class:`Waiting`).
"""
import time

from diagnostic_msgs.msg import KeyValue
from std_msgs.msg import String

from motoflex_ros.errors import MotoflexError
from motoflex_ros.nodes.interfaces import ACK_TOPIC, READY_TOPIC
from motoflex_ros.nodes.qos_profiles import latched_qos
from motoflex_ros.nodes.rig_node import MATCH_TIMEOUT_S

__all__ = ["AckGate", "ReadyWatch", "StallError", "Waiting",
           "WAIT_LOG_PERIOD_S"]

WAIT_LOG_PERIOD_S = 5.0  # a waiting node says what it waits for this often [s]


class StallError(MotoflexError):
    """A consumer stopped acknowledging (died or hung), or what a node waits for never came."""


class Waiting:
    """What a node waits for: logged when the wait starts and every WAIT_LOG_PERIOD_S; after
    ``stall_s`` [s] (None: never) waiting for the same thing, :meth:`still` raises StallError.
    """

    def __init__(self, node, stall_s=None):
        self.node = node
        self.stall_s = stall_s
        self._what = None
        self._since = self._logged = 0.0

    def still(self, what):
        """Note that the node still waits for ``what`` (a phrase); log it or give up."""
        now = time.monotonic()
        if what != self._what:      # progress: something else to wait for now
            self._what, self._since = what, now
        if self._logged == 0.0 or now - self._logged >= WAIT_LOG_PERIOD_S:
            self.node.get_logger().info(f"waiting for {what}")
            self._logged = now
        if self.stall_s is not None and now - self._since > self.stall_s:
            raise StallError(f"gave up after {self.stall_s:g} s waiting for {what}")


class ReadyWatch:
    """Collects the names announced on /rig/ready; ``ready()`` when all ``names`` are in and
    each of ``publishers`` is matched with every subscriber the ROS graph knows on its topic.

    A node announces itself once its subscriptions see their publishers; the publishers' side
    of the same match may come a moment later, and a reliable, volatile publisher drops what it
    sends before (the first messages of a run). After MATCH_TIMEOUT_S the match is not waited
    for any longer (a warning says so). While not ready, ``waiting`` (:class:`Waiting`, with
    ``stall_s``) says which nodes are missing.
    """

    def __init__(self, node, names, publishers=(), stall_s=None):
        self.node = node
        self.names = frozenset(names)
        self.publishers = tuple(publishers)
        self.seen = set()
        self.waiting = Waiting(node, stall_s)
        self._announced_at = None
        self._ready_sub = node.subscribe(String, READY_TOPIC, self._on_ready,
                                         qos=latched_qos())

    def _on_ready(self, msg):
        self.seen.add(msg.data)

    def ready(self):
        """True when every expected node has announced itself and our publishers are matched."""
        if not self.names <= self.seen:
            self.waiting.still(f"{', '.join(self.missing())} to announce on "
                               f"{self._ready_sub.topic_name}")
            return False
        if self._announced_at is None:
            self._announced_at = time.monotonic()
        if self.node.publishers_matched(self.publishers):
            return True
        if time.monotonic() - self._announced_at > MATCH_TIMEOUT_S:
            self.node.get_logger().warning(
                f"publishers not matched with every subscriber after {MATCH_TIMEOUT_S:g} s; "
                f"going on")
            self.publishers = ()
            return True
        return False

    def missing(self):
        """Expected nodes not yet ready, sorted."""
        return sorted(self.names - self.seen)


class AckGate:
    """Tracks acknowledgements of ``names`` and how far simulated time may advance."""

    def __init__(self, node, names, window_ns, stall_s):
        self.acked = {name: -1 for name in names}
        self.window_ns = int(window_ns)
        self.stall_s = stall_s
        self._progress = time.monotonic()
        node.subscribe(KeyValue, ACK_TOPIC, self._on_ack)

    def _on_ack(self, msg):
        if msg.key in self.acked:
            value = int(msg.value.split()[0])
            if value > self.acked[msg.key]:
                self.acked[msg.key] = value
                self._progress = time.monotonic()

    def slowest_ns(self):
        """Simulated time every consumer has handled [ns] (-1 if one has not acked yet)."""
        return min(self.acked.values(), default=2**62)

    def allows(self, t_ns):
        """May a message at simulated time ``t_ns`` go out now?"""
        return t_ns <= self.slowest_ns() + self.window_ns

    def all_acked(self, t_ns):
        """Has every consumer handled everything up to ``t_ns``?"""
        return self.slowest_ns() >= t_ns

    def check_stall(self):
        """Raise StallError if no acknowledgement arrived for ``stall_s`` seconds."""
        if time.monotonic() - self._progress > self.stall_s:
            late = sorted(n for n, t in self.acked.items() if t == self.slowest_ns())
            raise StallError(f"no acknowledgement for {self.stall_s:g} s from "
                             f"{', '.join(late)} (node died or hung?)")

    def touch(self):
        """Restart the stall timer (e.g. when the run starts)."""
        self._progress = time.monotonic()
