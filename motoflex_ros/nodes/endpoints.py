"""Who may publish to a rig node: the publishers of its own run, by GID, and nobody else.

The launcher gives every process of a run the folder ``$MOTOFLEX_ENDPOINTS`` (inside the run's
private work folder). Each node writes there, atomically, ``<node>.json``: {GID hex: topic} of
every publisher it creates, before it publishes anything on it. A node's :class:`InputGuard`
takes each message with its publisher's GID (:mod:`.transport`) and accepts it only if one of
the run's files lists that GID (an unknown GID makes it read the folder again once: a
publisher is always written down before its first message). Any other publisher on a topic
the node reads, a stray node or a second run in the same ROS domain, fails the run with
:class:`ForeignPublisher` naming the topic and the foreign node, before its message is used.
The trust comes from the file system, not from DDS: a foreign process cannot put its GID there
(the folder is the launcher's own, mode 0700).

The launcher's monitor also watches the ROS graph (:class:`GraphWatch`): a publisher on a rig
topic whose GID none of the run's files lists fails the run even before it sends anything (a
second run forced into the same domain is refused by the first, not only the other way round).

The guard also counts lost messages per publisher (DDS publication sequence numbers are per
writer; counted per subscription, two writers on one topic hid and faked gaps).

Without ``$MOTOFLEX_ENDPOINTS`` (a node started on its own, a real bench) every publisher is
accepted; the gap count stays per publisher.
"""
import json
import os
import time
from pathlib import Path

from motoflex_ros.errors import MotoflexError
from motoflex_ros.files import atomic_write_text

__all__ = ["ENDPOINTS_ENV", "ForeignPublisher", "RunEndpoints", "InputGuard", "GraphWatch",
           "RIG_TOPIC_PREFIXES", "GID_SIZE", "gid_text", "endpoint_gid"]

ENDPOINTS_ENV = "MOTOFLEX_ENDPOINTS"
GID_SIZE = 16   # bytes of a publisher's GID (rmw 7.3: RMW_GID_STORAGE_SIZE)
NAME_WAIT_S = 1.0   # longest wait for the graph to name a foreign publisher's node [s]
RIG_TOPIC_PREFIXES = ("/bench/", "/clock", "/identification/", "/vehicle/", "/rig/")


class ForeignPublisher(MotoflexError):
    """A message came from a publisher that is not one of the run's own."""


class RunEndpoints:
    """The publisher GIDs of one run, as its nodes wrote them to ``folder``."""

    def __init__(self, folder, node_name=None):
        self.folder = Path(folder)
        self.node_name = node_name
        self.own = {}
        self.owners = {}   # GID bytes -> node name

    @classmethod
    def from_environment(cls, node_name=None):
        """The run's endpoints if the launcher set ``$MOTOFLEX_ENDPOINTS``, else None."""
        folder = os.environ.get(ENDPOINTS_ENV)
        return cls(folder, node_name) if folder else None

    def register(self, publisher, gid):
        """Write down one of this node's publishers, whose GID is ``gid`` (bytes; call before
        it publishes)."""
        self.own[gid.hex()] = publisher.topic_name
        self.owners[gid] = self.node_name
        atomic_write_text(self.folder / f"{self.node_name}.json", json.dumps(self.own))

    def owner(self, gid):
        """Name of the run's node that owns publisher ``gid`` (bytes), or None."""
        if gid not in self.owners:
            self.reload()
        return self.owners.get(gid)

    def reload(self):
        """Read every node's file again."""
        for path in self.folder.glob("*.json"):
            try:
                gids = json.loads(path.read_text())
            except (OSError, ValueError):
                continue   # a file of a node that is going away; the next miss reads again
            self.owners.update({bytes.fromhex(g): path.stem for g in gids})


class InputGuard:
    """Per message: is its publisher one of the run's (else ForeignPublisher), and did that
    publisher's sequence numbers skip (lost messages, counted in ``gaps``)?"""

    def __init__(self, node, endpoints, count_gaps=lambda sub: True):
        self.node = node
        self.endpoints = endpoints
        self.count_gaps = count_gaps
        self.gaps = 0
        self._last_seq = {}
        self._trusted = set()
        self._only = {}   # subscription -> names of the run's nodes it accepts
        self._verified = {}   # plain path: subscription -> publisher count checked in the graph
        self.joined_late = set()   # subscriptions made after their publishers began

    def only_from(self, sub, names):
        """Accept on ``sub`` only messages of the run's nodes called ``names``."""
        self._only[sub] = frozenset(names)

    def check(self, sub, gid, seq):
        """Raise ForeignPublisher for a message of ``sub`` from an unknown publisher; count a
        gap in the sequence numbers of its publisher. ``gid`` None (the plain rclpy transport,
        which does not tell who sent a message): :meth:`check_topic`."""
        if gid is None:
            return self.check_topic(sub, seq)
        if self.endpoints is not None and gid not in self._trusted:
            if self.endpoints.owner(gid) is None:
                raise ForeignPublisher(self.describe_foreign(sub.topic_name, gid))
            self._trusted.add(gid)
        only = self._only.get(sub)
        if only is not None and self.endpoints is not None and \
                self.endpoints.owner(gid) not in only:
            raise ForeignPublisher(f"{sub.topic_name}: node '{self.endpoints.owner(gid)}' of "
                                   f"this run published here; only {', '.join(sorted(only))} "
                                   f"may; its message was refused and the run stopped")
        self._count_gap(sub, gid, seq)

    def check_topic(self, sub, seq):
        """The check without the sender's identity (plain rclpy transport), before the message
        is used: whenever the count of publishers matched with ``sub`` changes, every publisher
        the ROS graph lists on its topic must be one of the run's (the graph may list a new
        publisher, or the run's file name it, a moment after it matched: waited for up to
        ``NAME_WAIT_S`` [s], then ForeignPublisher); gaps are counted while the topic has one
        publisher (sequence numbers are per publisher)."""
        count = sub.get_publisher_count()
        if self.endpoints is not None and self._verified.get(sub) != count:
            deadline = time.monotonic() + NAME_WAIT_S
            while True:
                gids = [endpoint_gid(i) for i in self.node.get_publishers_info_by_topic(
                    sub.topic_name)]
                known = len(gids) >= count and all(self.endpoints.owner(g) is not None
                                                   for g in gids)
                if known or time.monotonic() >= deadline:
                    break
                time.sleep(0.05)
            for gid in gids:
                self.check(sub, gid, 0)   # raises for one that is still unknown
            if len(gids) < count:
                raise ForeignPublisher(_foreign(sub.topic_name, "a node the ROS graph does not "
                                                "list", b"", "its message was refused"))
            self._verified[sub] = count
        if count == 1:
            self._count_gap(sub, None, seq)

    def _count_gap(self, sub, gid, seq):
        if not seq or not self.count_gaps(sub):
            return
        key = (sub, gid)
        last = self._last_seq.get(key)
        if last is None:
            # a subscription made after its publisher began (a recorder discovering topics
            # of a running graph): what that publisher sent before is not lost, it was never
            # ours to receive; count from its first message here
            last = seq - 1 if sub in self.joined_late else 0
        if seq > last + 1:
            lost = seq - last - 1
            self.gaps += lost
            sender = gid_text(gid) if gid else "the only one"
            self.node.get_logger().error(f"gap on {sub.topic_name}: {lost} message(s) lost "
                                         f"(publisher {sender}, sequence {last} -> {seq})")
        self._last_seq[key] = max(seq, last)

    def describe_foreign(self, topic, gid):
        """The ForeignPublisher message for a message on ``topic`` from ``gid``."""
        return _foreign(topic, self._node_of(topic, gid), gid, "its message was refused")

    def _node_of(self, topic, gid):
        deadline = time.monotonic() + NAME_WAIT_S
        while True:
            for info in self.node.get_publishers_info_by_topic(topic):
                if endpoint_gid(info) == gid and not info.node_name.startswith("_NODE_"):
                    return _label(info)
            if time.monotonic() > deadline:
                return "a node the ROS graph does not name"
            time.sleep(0.05)


class GraphWatch:
    """Every ``period_s`` [s]: does the ROS graph show a publisher on a rig topic that is not
    one of the run's? One whose GID no file of the run lists ``grace_s`` [s] after it was first
    seen (a node writes its file a moment after creating the publisher, and discovery may be
    quicker) raises ForeignPublisher, even if it is gone by then (a second run's node that
    stopped at once on this run's messages was still there)."""

    def __init__(self, node, endpoints, period_s=0.2, grace_s=1.0):
        self.node = node
        self.endpoints = endpoints
        self.period_s = period_s
        self.grace_s = grace_s
        self._next = 0.0
        self._unknown = {}   # GID -> (when first seen, topic, node label)

    def check(self):
        """Look at the graph if the period has passed."""
        now = time.monotonic()
        if self.endpoints is None or now < self._next:
            return
        self._next = now + self.period_s
        namespace = self.node.get_namespace().rstrip("/")   # this rig's topics only
        prefixes = tuple(namespace + p for p in RIG_TOPIC_PREFIXES)
        for topic, _ in self.node.get_topic_names_and_types():
            if topic.startswith(prefixes):
                for info in self.node.get_publishers_info_by_topic(topic):
                    gid, first = endpoint_gid(info), self._unknown.get(endpoint_gid(info))
                    if first is None or "_NODE_" in first[2]:   # the name may come later
                        self._unknown[gid] = (first[0] if first else now, topic, _label(info))
        for gid, (seen, topic, label) in list(self._unknown.items()):
            if self.endpoints.owner(gid) is not None:
                del self._unknown[gid]
            elif now - seen > self.grace_s:
                raise ForeignPublisher(_foreign(topic, label, gid, "seen in the ROS graph"))


def gid_text(gid):
    """A GID as the dotted hex ROS tools print."""
    return ".".join(f"{b:02x}" for b in gid)


def endpoint_gid(info):
    """The GID (bytes) of a publisher as the ROS graph lists it (rclpy TopicEndpointInfo)."""
    return bytes(info.endpoint_gid[:GID_SIZE])


def _label(info):
    """"node '/ns/name'" of a TopicEndpointInfo."""
    return f"node '{info.node_namespace.rstrip('/')}/{info.node_name}'"


def _foreign(topic, label, gid, what):
    gid = f" (GID {gid_text(gid)})" if gid else ""
    return (f"foreign publisher on {topic}: {label}{gid} is not one of this "
            f"run's nodes; {what} and the run stopped (another run in this ROS domain, or a "
            f"stray publisher?)")
