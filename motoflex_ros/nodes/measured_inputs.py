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
"""
import time

import numpy as np
from geometry_msgs.msg import PointStamped, PoseArray, PoseStamped, WrenchStamped
from rclpy.qos import HistoryPolicy, QoSProfile, ReliabilityPolicy
from std_msgs.msg import Empty

from motoflex_ros.nodes.params import Param, ParameterError

__all__ = ["MEASURED_PARAMS", "MeasuredInputs", "MARKER_MSGS"]

MARKER_MSGS = {"PoseArray": PoseArray, "PointStamped": PointStamped, "PoseStamped": PoseStamped}

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
)


def _stamp_ns(msg):
    return msg.header.stamp.sec * 1_000_000_000 + msg.header.stamp.nanosec


class MeasuredInputs:
    """The measured-mode subscriptions of ``node`` and what they received."""

    def __init__(self, node, params):
        from motoflex_ros.identify.bench_file import load_bench
        if not params["bench_file"]:
            raise ParameterError(f"node '{node.get_name()}': parameter 'bench_file' is "
                                 f"required in mode measured (a bench file: bench, "
                                 f"loaded_end, markers, sensor)")
        self.node = node
        self.bench = load_bench(params["bench_file"])
        base = f"bench/{self.bench.name}"   # relative: in the node's namespace, as the rig's
        reliability = (ReliabilityPolicy.RELIABLE if params["qos"] == "reliable"
                       else ReliabilityPolicy.BEST_EFFORT)
        qos = QoSProfile(depth=1, history=HistoryPolicy.KEEP_ALL, reliability=reliability)
        self.loads, self.frames, self.subscriptions = [], [], []
        self.per_marker = params["marker_msg"] != "PoseArray"
        self.received = {}
        load_topic = params["load_topic"] or f"{base}/load"
        markers_topic = params["markers_topic"] or f"{base}/markers/measured"
        self.subscriptions.append(node.create_subscription(WrenchStamped, load_topic,
                                                           self._load, qos))
        if self.per_marker:
            n = params["n_markers"] or self.bench.n_markers
            if not n or n < 3:
                raise ParameterError(f"node '{node.get_name()}': parameter 'n_markers' must "
                                     f"be >= 3 for per-marker topics (the bench file has "
                                     f"markers: from_data)")
            self.frames = [[] for _ in range(n)]
            for i in range(n):
                self.subscriptions.append(node.create_subscription(
                    MARKER_MSGS[params["marker_msg"]], f"{markers_topic}/m{i + 1}",
                    self._marker(i), qos))
        else:
            self.subscriptions.append(node.create_subscription(PoseArray, markers_topic,
                                                               self._pose_array, qos))
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

    def _count(self, what):
        self.received[what] = self.received.get(what, 0) + 1
        self.last_input = time.monotonic()

    def _load(self, msg):
        w = msg.wrench
        self.loads.append((_stamp_ns(msg), w.force.x, w.force.y, w.force.z, w.torque.x,
                           w.torque.y, w.torque.z))
        self._count("load")

    def _pose_array(self, msg):
        points = [(p.position.x, p.position.y, p.position.z) for p in msg.poses]
        self.frames.append((_stamp_ns(msg), points))
        self._count("markers")

    def _marker(self, i):
        def callback(msg):
            p = msg.point if hasattr(msg, "point") else msg.pose.position
            self.frames[i].append((_stamp_ns(msg), (p.x, p.y, p.z)))
            self._count(f"m{i + 1}")
        return callback

    def _asked(self, _msg):
        self.asked = True

    def due(self):
        """Whether to identify now (asked, or idle long enough after some input); resets."""
        idle = (self.idle_s > 0 and self.last_input is not None
                and time.monotonic() - self.last_input >= self.idle_s)
        if (self.asked or idle) and self.loads:
            self.asked, self.last_input = False, None
            return True
        return False

    def measurements(self):
        """The core's Measurements of everything received (sorted by stamp per topic)."""
        from motoflex_ros.identify.measurements import live_measurements
        loads = sorted(self.loads)
        if self.per_marker:
            markers = [sorted(stream) for stream in self.frames]
        else:
            markers = sorted(self.frames, key=lambda f: f[0])
        return live_measurements(np.array([row[0] for row in loads], np.int64),
                                 np.array([row[1:] for row in loads], float), markers,
                                 self.per_marker, self.bench, "live topics")
