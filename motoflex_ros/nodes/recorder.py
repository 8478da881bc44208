"""recorder: writes every topic of a run to a rosbag2 MCAP bag (``bag`` parameter: directory).

Subscribes raw (serialized CDR bytes, no deserialization) to the topics listed in ``topics``,
once they have a publisher, or, if that list is empty, to every topic it discovers except the
rig's own /rig/* and the ROS bookkeeping topics. Each message is logged on the run's simulated
clock (``log_time`` 'stamp', the default): at its header stamp, or, without one, at the latest
stamp recorded or the recorder's /clock time (:mod:`motoflex_ros.record.log_time`); with
'receive' at its wall-clock receive time [ns], as ``ros2 bag record`` does. The MCAP file is
finished and metadata.yaml written on SIGINT, SIGTERM
and at the end of a run; a killed recorder leaves an MCAP that ``motoflex bag repair``
salvages. With ``ack`` the recorder acknowledges recorded /clock times on /rig/ack, so a
pacing source never outruns it; without, it lets messages gather for ``batch_period`` between
two waits (fewer wake-ups, less CPU; the readers' keep-all queues hold them meanwhile).

Under a namespace (``-r __ns:=/rig_a``) it records that rig's topics only, and names them in the
bag as from the rig's root (/rig_a/bench/x as /bench/x), so that replay, conversion and report
read a namespaced run like any other; ``motoflex replay`` republishes it under any namespace.

Each topic is recorded with the QoS profiles its publishers offer (metadata.yaml, as
``ros2 bag record`` does: a replay offers them again) and subscribed with their durability
(transient local when all of them offer it: latched messages sent before the recorder came
are recorded too). The rig's transforms, TransformStamped on /rig/tf and /rig/tf_static, go into
the bag as /tf and /tf_static (tf2_msgs/msg/TFMessage: :mod:`motoflex_ros.record.tf_bag`).
"""
import sys
import time

from rclpy.qos import DurabilityPolicy

from motoflex_ros.errors import MotoflexError
from motoflex_ros.nodes.cdr import clock_ns_from_cdr
from motoflex_ros.nodes.conversions import qos_dict
from motoflex_ros.nodes.interfaces import RELIABLE, RIG_TOPICS, Topic, message_class
from motoflex_ros.nodes.node_main import run_node
from motoflex_ros.nodes.params import Param, ParameterError
from motoflex_ros.nodes.qos_profiles import reliable_qos
from motoflex_ros.nodes.rig_node import RigNode
from motoflex_ros.record.log_time import SimLogTime
from motoflex_ros.record.mcap_bag import BagWriter
from motoflex_ros.record.tf_bag import LIVE_TYPE as TF_LIVE_TYPE
from motoflex_ros.record.tf_bag import TF_TOPICS, TF_TYPE, TfBatcher

__all__ = ["Recorder", "main", "IGNORED_PREFIXES"]

IGNORED_PREFIXES = ("/rig/", "/rosout", "/parameter_events")
CLOCK_TYPE = "rosgraph_msgs/msg/Clock"


class Recorder(RigNode):
    """Raw subscriptions -> :class:`motoflex_ros.record.mcap_bag.BagWriter`."""

    NAME = "recorder"
    PARAMS = (
        Param("bag", "", description="bag directory to create (must not exist)"),
        Param("topics", (), description="topics to record, under the node's namespace "
              "(empty: every topic discovered there)"),
        Param("late_topics", (), description="topics of ``topics`` that may appear after the "
              "run started (not waited for)"),
        Param("chunk_size", 262144, 4096, 64 * 2**20, description="MCAP chunk size [bytes]"),
        Param("compression", "zstd", choices=("zstd", "lz4", "none")),
        Param("log_time", "stamp", choices=("stamp", "receive"),
              description="log time: the simulated stamp, or the wall-clock receive time"),
        Param("ack", False, description="acknowledge recorded /clock times on /rig/ack"),
        Param("discovery_period", 0.2, 0.01, 60.0, description="topic discovery period [s]"),
        Param("batch_period", 0.005, 0.0, 1.0,
              description="pause between two waits when not acknowledging [s]"),
    )
    TOPICS = RIG_TOPICS + (
        Topic("sub", "<each topic of topics>", "the topic's type", "the publishers' offered "
              "QoS (reliable, keep all where they are reliable)", "recorded into the bag; "
              "/rig/tf and /rig/tf_static are written as /tf and /tf_static "
              "(tf2_msgs/msg/TFMessage)", when="as the topics appear"),
        Topic("pub", "rig/ack", "diagnostic_msgs/msg/KeyValue", RELIABLE,
              "recorded /clock times (value [ns]), pacing a replay", when="ack true"),
    )

    def __init__(self):
        super().__init__()
        p = self.params
        if not p["bag"]:
            raise ParameterError("node 'recorder': parameter 'bag' is required (bag directory)")
        self.writer = BagWriter(p["bag"], chunk_size=p["chunk_size"],
                                compression=p["compression"])
        self.wanted = tuple(_rooted(t) for t in p["topics"])
        self.late = {_rooted(t) for t in p["late_topics"]}
        self.recorded = {}
        self.batchers = []
        self.sim_log = SimLogTime()
        self._next_discovery = 0.0
        self.discover()

    def discover(self):
        """Subscribe to every wanted topic that has appeared on the graph."""
        for name, types in self.get_topic_names_and_types():
            topic = self.in_rig(name)
            if topic is None or topic in self.recorded or not self._wants(topic):
                continue
            type_name = types[0]
            offered = self._offered(name)
            if not offered:   # only subscribers so far: wait for a publisher and its QoS
                continue
            if topic in TF_TOPICS:
                self.writer.add_topic(TF_TOPICS[topic], TF_TYPE, offered)
                callback = self._tf_callback(topic)
            else:
                self.writer.add_topic(topic, type_name, offered)
                callback = (self._clock_callback if topic == "/clock"
                            else self._callback(topic, type_name))
            sub = self.subscribe(message_class(type_name), name, callback, raw=True,
                                 qos=self._qos_for(offered))
            if self._ready_sent or not self.wanted:
                # found while the graph runs (or any topic of a discovering recorder): its
                # publishers may have sent before this subscription; not a loss
                self.guard.joined_late.add(sub)
            self.recorded[topic] = type_name
        self._next_discovery = time.monotonic() + self.params["discovery_period"]

    def in_rig(self, name):
        """The topic ``name`` (fully qualified) as the bag names it: relative to this node's
        namespace, from '/' (``/rig_a/bench/x`` -> ``/bench/x`` under /rig_a); None for a
        topic of another namespace."""
        namespace = self.get_namespace().rstrip("/")
        if not namespace:
            return name
        return name[len(namespace):] if name.startswith(namespace + "/") else None

    def _wants(self, topic):
        if self.wanted:
            return topic in self.wanted
        return topic in TF_TOPICS or not topic.startswith(IGNORED_PREFIXES)

    def _log_ns(self, type_name, data):
        """The log time [ns] of a received message (``log_time``)."""
        if self.params["log_time"] == "receive":
            return time.time_ns()
        return self.sim_log.of(type_name, data, self.get_clock().now().nanoseconds)

    def _callback(self, topic, type_name):
        write = self.writer.write

        def record(data):
            write(topic, self._log_ns(type_name, data), data)
        return record

    def _tf_callback(self, topic):
        bag_topic = TF_TOPICS[topic]
        batcher = TfBatcher(lambda ns, data: self.writer.write(bag_topic, ns, data))
        self.batchers.append(batcher)

        def record(data):
            batcher.add(self._log_ns(TF_LIVE_TYPE, data), data)
        return record

    def _offered(self, topic):
        """The distinct QoS profiles the publishers of ``topic`` offer (rosbag2's numbers)."""
        profiles = []
        for info in self.get_publishers_info_by_topic(topic):
            profile = qos_dict(info.qos_profile)
            if profile not in profiles:
                profiles.append(profile)
        return profiles

    @staticmethod
    def _qos_for(offered):
        """Reliable keep-all, transient local if every offered profile is (as rosbag2)."""
        qos = reliable_qos()
        if all(p["durability"] == DurabilityPolicy.TRANSIENT_LOCAL.value for p in offered):
            qos.durability = DurabilityPolicy.TRANSIENT_LOCAL
        return qos

    def _clock_callback(self, data):
        self.writer.write("/clock", self._log_ns(CLOCK_TYPE, data), data)
        if self.params["ack"]:
            self.processed(clock_ns_from_cdr(data))

    def inputs_ready(self):
        """Ready when every listed topic (discovery mode: at least one topic) is subscribed
        and sees a publisher.
        """
        late = self.late
        listed = (all(t in self.recorded for t in self.wanted if t not in late) if self.wanted
                  else self.recorded)
        return bool(listed) and all(sub.get_publisher_count() > 0 for sub in self._checked
                                    if self.in_rig(sub.topic_name) not in late)

    def step(self, spinner):
        """Record what arrived; look for new topics now and then."""
        if time.monotonic() >= self._next_discovery:
            self.discover()
        super().step(spinner)
        for batcher in self.batchers:
            batcher.flush()
        if not self.params["ack"] and self.params["batch_period"] > 0:
            time.sleep(self.params["batch_period"])

    def close(self, reason):
        """Finish the MCAP file and write metadata.yaml; a write that fails (a full disk) is
        one error line naming the file, exit code 2 (the file is closed all the same)."""
        problem = None
        try:
            for batcher in self.batchers:
                batcher.flush()
        except MotoflexError as exc:
            problem = exc
        try:
            self.writer.close()
        except MotoflexError as exc:
            problem = problem or exc
        if problem is None:
            self.get_logger().info(f"bag {self.writer.path} closed ({reason}): "
                                   f"{self.writer.message_count} messages")
        else:
            self.get_logger().error(f"bag {self.writer.path} not finished: {problem}")
            self.exit_code = 2
        super().close(reason)


def _rooted(topic):
    """A listed topic name from the rig's root: 'bench/x' and '/bench/x' are '/bench/x'."""
    return "/" + topic.lstrip("/")


def main(args=None):
    """Console script ``recorder``."""
    return run_node(Recorder, args)


if __name__ == "__main__":
    sys.exit(main())
