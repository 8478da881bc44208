"""The identification node's inputs in ``mode: measured``: a real rig's standard topics.

Subscriptions (rclpy message objects in, numpy out; no numerics here): the load cell
(geometry_msgs/WrenchStamped) and the markers (geometry_msgs/PoseArray per frame, or one
PointStamped / PoseStamped topic per marker, ``<markers_topic>/m1``, ``/m2``, ...), each kept
with its header stamp in arrival order; the core sorts nothing out of them but what it must
(:mod:`motoflex_ros.identify.measurements`: frames assembled by stamp, the streams synchronised
by approximate-time matching after the bench file's latency). No acknowledgements: a rig does
not wait for the identification. Identification is due when a message arrives on the
identify topic (std_msgs/Empty) or, with ``idle_timeout_s`` > 0, when no input has arrived for
that long (wall clock) after some did.

Memory is bounded before any work (issue 23, point 3): at most ``max_frames`` load samples and
marker frames are kept (:class:`motoflex_ros.nodes.kept_frames.KeptRows`, numpy arrays of
fixed row size: about (56 + 32 N) bytes a frame of N markers, 160 MB at the default 600,000
frames of 4 markers, 10 minutes at 1 kHz). Past the bound the OLDEST messages are dropped and
counted (``dropped_oldest_load``, ``dropped_oldest_markers`` in the result's message counts, a
warning in the log when it starts): the identification uses the most recent stretch. A
message larger than the bound allows (a PoseArray of more than MAX_BURST_FRAMES frames of
markers, any other message above MAX_MESSAGE_BYTES) is dropped by its serialized size,
before it is deserialized, and counted (``oversized``). A best-effort subscription keeps at
most QUEUE_DEPTH messages waiting (a reliable one leaves the flow control to the publisher).
"""
import time

import numpy as np
from geometry_msgs.msg import PointStamped, PoseArray, PoseStamped, WrenchStamped
from rclpy.qos import HistoryPolicy, QoSProfile, ReliabilityPolicy
from rclpy.serialization import deserialize_message
from std_msgs.msg import Empty

from motoflex_ros.nodes.cdr import points_from_cdr, wrench_vector_from_cdr
from motoflex_ros.nodes.kept_frames import KeptRows
from motoflex_ros.nodes.params import Param, ParameterError
from motoflex_ros.nodes.stamps import time_ns

__all__ = ["MEASURED_PARAMS", "MeasuredInputs", "MARKER_MSGS"]

MARKER_MSGS = {"PoseArray": PoseArray, "PointStamped": PointStamped, "PoseStamped": PoseStamped}
MAX_BURST_FRAMES = 64       # marker frames one PoseArray may carry
FROM_DATA_MARKERS = 16      # markers per frame the bound assumes with markers: from_data
MAX_MESSAGE_BYTES = 4096    # a load, point or pose message (header and frame id included)
POSE_BYTES = 56             # 7 float64 of a serialized geometry_msgs/Pose
QUEUE_DEPTH = 10_000        # best effort: messages waiting for the node at most

MEASURED_PARAMS = (
    Param("bench_file", "", description="mode measured: the bench file (YAML: bench, "
                                        "loaded_end, markers, sensor)"),
    Param("load_topic", "", description="mode measured: the load cell's WrenchStamped topic "
                                        "('': bench/<bench>/load)"),
    Param("markers_topic", "", description="mode measured: the markers' topic ('': "
                                           "bench/<bench>/markers/measured; per-marker "
                                           "messages on <topic>/m1, /m2, ...)"),
    Param("marker_msg", "PoseArray", choices=tuple(MARKER_MSGS),
          description="mode measured: the markers' message type"),
    Param("n_markers", 0, 0, 1000, description="mode measured, per-marker topics with "
                                               "markers: from_data: how many (0: the bench "
                                               "file's)"),
    Param("identify_topic", "", description="mode measured: std_msgs/Empty asking for the "
                                            "identification ('': bench/<bench>/identify)"),
    Param("idle_timeout_s", 0.0, 0.0, 3600.0,
          description="mode measured: identify after this long without input [s] (0: only "
                      "when asked)"),
    Param("qos", "best_effort", choices=("best_effort", "reliable"),
          description="mode measured: the subscriptions' reliability (best_effort matches "
                      "every publisher)"),
    Param("max_frames", 600_000, 10, 100_000_000,
          description="mode measured: most load samples and marker frames kept; beyond, the "
                      "oldest messages are dropped and counted [-]"),
)


class MeasuredInputs:
    """The measured-mode subscriptions of ``node`` and what they received."""

    def __init__(self, node, params):
        from motoflex_ros.formats.bench_file import load_bench
        if not params["bench_file"]:
            raise ParameterError(f"node '{node.get_name()}': parameter 'bench_file' is "
                                 f"required in mode measured (a bench file: bench, "
                                 f"loaded_end, markers, sensor)")
        self.node = node
        self.bench = load_bench(params["bench_file"])
        base = f"bench/{self.bench.name}"   # relative: in the node's namespace, as the rig's
        reliability = (ReliabilityPolicy.RELIABLE if params["qos"] == "reliable"
                       else ReliabilityPolicy.BEST_EFFORT)
        qos = (QoSProfile(depth=1, history=HistoryPolicy.KEEP_ALL, reliability=reliability)
               if params["qos"] == "reliable" else
               QoSProfile(depth=QUEUE_DEPTH, history=HistoryPolicy.KEEP_LAST,
                          reliability=reliability))
        self.subscriptions = []
        self.per_marker = params["marker_msg"] != "PoseArray"
        self.received = {}
        self.max_frames = params["max_frames"]
        self.warned = set()
        self.loads = KeptRows(self.max_frames, 6)
        load_topic = params["load_topic"] or f"{base}/load"
        markers_topic = params["markers_topic"] or f"{base}/markers/measured"
        self._subscribe(WrenchStamped, load_topic, self._load, qos, MAX_MESSAGE_BYTES,
                        wrench_vector_from_cdr)
        if self.per_marker:
            n = params["n_markers"] or self.bench.n_markers
            if not n or n < 3:
                raise ParameterError(f"node '{node.get_name()}': parameter 'n_markers' must "
                                     f"be >= 3 for per-marker topics (the bench file has "
                                     f"markers: from_data)")
            self.frames = [KeptRows(self.max_frames, 3) for _ in range(n)]
            for i in range(n):
                self._subscribe(MARKER_MSGS[params["marker_msg"]], f"{markers_topic}/m{i + 1}",
                                self._marker(i), qos, MAX_MESSAGE_BYTES)
        else:
            n = params["n_markers"] or self.bench.n_markers or FROM_DATA_MARKERS
            self.frames = KeptRows(self.max_frames * n, 3)
            self._subscribe(PoseArray, markers_topic, self._pose_array, qos,
                            MAX_MESSAGE_BYTES + MAX_BURST_FRAMES * n * POSE_BYTES,
                            points_from_cdr)
        node.create_subscription(Empty, params["identify_topic"] or f"{base}/identify",
                                 self._asked, 10)
        self.idle_s = params["idle_timeout_s"]
        self.last_input = None
        self.asked = False
        node.get_logger().info(f"mode measured: bench {self.bench.name} ({self.bench.source}); "
                               f"load {load_topic}, markers {markers_topic} "
                               f"({params['marker_msg']})")

    def inputs_ready(self):
        """Every data subscription sees a publisher (the identify topic's is not waited for:
        a rig asks when it is done)."""
        return all(sub.get_publisher_count() > 0 for sub in self.subscriptions)

    def _subscribe(self, msg_type, topic, callback, qos, max_bytes, parse=None):
        """A raw subscription: a message above ``max_bytes`` is dropped and counted before it
        is deserialized; the others go to ``callback`` as ``parse(bytes)`` (default: the
        message)."""
        def take(data):
            if len(data) > max_bytes:
                self._warn("oversized", f"{topic}: a message of {len(data)} bytes is above the "
                                        f"{max_bytes} this node keeps of one; dropped, counted "
                                        f"as 'oversized'")
                self._count("oversized")
                return
            callback(parse(data) if parse else deserialize_message(data, msg_type))
        self.subscriptions.append(self.node.create_subscription(msg_type, topic, take, qos,
                                                                raw=True))

    def _warn(self, key, text):
        if key not in self.warned:
            self.warned.add(key)
            self.node.get_logger().warning(text)

    def _count(self, what):
        self.received[what] = self.received.get(what, 0) + 1
        self.last_input = time.monotonic()

    def _keep(self, store, what, stamp, rows):
        before = store.dropped_messages
        store.push(stamp, rows)
        if store.dropped_messages > before:
            self._warn("bound", f"{self.max_frames} frames kept (parameter max_frames): the "
                                f"oldest messages are dropped from now on, and counted")
            key = f"dropped_oldest_{what}"
            self.received[key] = self.received.get(key, 0) + store.dropped_messages - before

    def _load(self, stamped):
        self._keep(self.loads, "load", *stamped)
        self._count("load")

    def _pose_array(self, stamped):
        self._keep(self.frames, "markers", *stamped)
        self._count("markers")

    def _marker(self, i):
        def callback(msg):
            p = msg.point if hasattr(msg, "point") else msg.pose.position
            self._keep(self.frames[i], "markers", time_ns(msg.header.stamp), (p.x, p.y, p.z))
            self._count(f"m{i + 1}")
        return callback

    def _asked(self, _msg):
        self.asked = True

    def due(self):
        """Whether to identify now (asked, or idle long enough after some input); resets."""
        idle = (self.idle_s > 0 and self.last_input is not None
                and time.monotonic() - self.last_input >= self.idle_s)
        if (self.asked or idle) and self.loads.size:
            self.asked, self.last_input = False, None
            return True
        return False

    def measurements(self):
        """The core's Measurements of everything received (sorted by stamp per topic)."""
        from motoflex_ros.identify.measurements import live_measurements
        stamps, wrench, _ = self.loads.rows()
        order = np.argsort(stamps, kind="stable")
        if self.per_marker:
            markers = [sorted((s, tuple(v)) for s, v in zip(*stream.rows()[:2]))
                       for stream in self.frames]
        else:
            markers = sorted(self.frames.messages(), key=lambda f: f[0])
        return live_measurements(stamps[order], wrench[order], markers, self.per_marker,
                                 self.bench, "live topics")
