"""The plain rclpy transport: rclpy's subscriptions, publishers and executor (:mod:`.transport`).

Chosen with ``MOTOFLEX_TRANSPORT=rclpy``. It needs nothing of rcl or rmw beyond rclpy's public
API, so it runs on any ROS 2 release rclpy runs on; it is slower than the ctypes path (a
campaign's node graph 1.19x the wall time and 1.30x the CPU, ``benchmarks/bench_transport.py``)
and knows less about each message:

- rclpy 7.1 (Jazzy) gives a subscription callback its MessageInfo (timestamps and sequence
  numbers) but not the publisher's GID. Each message therefore reaches
  :meth:`.endpoints.InputGuard.check` without its sender: the trust check looks at the topic's
  publishers in the ROS graph instead (:meth:`.endpoints.InputGuard.check_topic`): when the
  count of matched publishers changes, every one the graph lists must be the run's, before the
  message is used, so a foreign publisher stops the run at the first message on its topic
  after it matched, whoever sent that message; gaps are counted only while a topic has one
  publisher (the acknowledgements of /rig/ack, with one writer per node, go unchecked).
- A publisher's own GID comes from the ROS graph (the node's own endpoint on the topic), which
  lists it as soon as it is created.
"""
from rclpy.executors import SingleThreadedExecutor

from motoflex_ros.errors import MotoflexError
from motoflex_ros.nodes.endpoints import endpoint_gid

__all__ = ["Spinner", "publisher_gid"]


def publisher_gid(publisher, node, known=()):
    """GID (bytes) of a new rclpy ``publisher`` of ``node``, as the ROS graph lists it: the
    node's endpoint on its topic that is not one of ``known`` (the GIDs of its earlier
    publishers)."""
    topic = publisher.topic_name
    own = [endpoint_gid(info) for info in node.get_publishers_info_by_topic(topic)
           if info.node_name == node.get_name() and info.node_namespace == node.get_namespace()]
    fresh = [gid for gid in own if gid not in known]
    if len(fresh) != 1:
        raise MotoflexError(f"{topic}: the ROS graph lists {len(fresh)} new publishers of this "
                            f"node, expected 1")
    return fresh[0]


class Spinner:
    """rclpy's SingleThreadedExecutor on one node waits and runs the first callback; then
    every subscription is drained with ``Subscription.handle.take_message``, the call the
    executor itself makes. (One executor turn per message builds a wait set each time: 169 us
    of CPU per message against 7.8 us so, ``benchmarks/bench_transport.py``; the recorder fell
    behind and lost the tail of a campaign's bag.) Every subscription's callback also gets the
    MessageInfo, so that ``check(sub, None, publication sequence number)`` sees each message
    before the node's callback does."""

    def __init__(self, node, check):
        self.node = node
        self.check = check
        self.executor = SingleThreadedExecutor(context=node.context)
        self.executor.add_node(node)
        self._wrapped = set()
        self._count = 0

    def spin_once(self, timeout_s):
        """Handle every message available within ``timeout_s`` [s]; returns the count."""
        subs = list(self.node.subscriptions)
        for sub in subs:
            if sub not in self._wrapped:
                sub.callback = self._checked(sub, sub.callback)
                self._wrapped.add(sub)
        start = self._count
        self.executor.spin_once(timeout_sec=timeout_s)
        if self._count > start or timeout_s == 0:
            for sub in subs:
                self._drain(sub)
        return self._count - start

    @staticmethod
    def _drain(sub):
        callback = sub.callback
        with sub.handle:
            while True:
                taken = sub.handle.take_message(sub.msg_type, sub.raw)
                if taken is None:
                    return
                callback(*taken)

    def _checked(self, sub, callback):
        def with_info(msg, info):
            self.check(sub, None, info["publication_sequence_number"])
            callback(msg)
            self._count += 1
        return with_info
