"""The identification node's ``mode: measured`` (issue 17): a real rig, no FE model, no lock-step.

The node reads the bench file (``bench_file``), subscribes to the load cell
(geometry_msgs/WrenchStamped, ``load_topic``) and the markers (``markers_topic``: one
geometry_msgs/PoseArray per frame, or with ``marker_msg`` PointStamped / PoseStamped one topic
``<markers_topic>/m<i>`` per marker), keeps every message as it comes (asynchronous: any order
across topics, any rates; :mod:`.measured_inputs`) and acknowledges nothing. A message on
``identify_topic`` (std_msgs/Empty), or ``idle_timeout_s`` without input, identifies what has
arrived (header stamps, the core's approximate-time matching,
:func:`motoflex_ros.identify.measured.identify_measured`), publishes it on
identification/results and writes ``result_file``. Topic names default to
bench/<bench>/{load, markers/measured, identify} (relative: in the node's namespace) and can
be set or remapped (``-r``).
"""
from diagnostic_msgs.msg import DiagnosticArray

from motoflex_ros.errors import MotoflexError
from motoflex_ros.formats.json_yaml import to_jsonable, write_results
from motoflex_ros.identify.measured import identify_measured
from motoflex_ros.nodes.interfaces import Topic
from motoflex_ros.nodes.measured_inputs import MeasuredInputs
from motoflex_ros.nodes.result_messages import identification_statuses

__all__ = ["MeasuredIdentification", "MEASURED_TOPICS"]

MEASURED_TOPICS = (
    Topic("sub", "bench/<bench>/load (load_topic)", "geometry_msgs/msg/WrenchStamped",
          "best effort or reliable (qos), keep all", "the load cell", when="mode measured"),
    Topic("sub", "bench/<bench>/markers/measured (markers_topic)",
          "geometry_msgs/msg/PoseArray (or per marker .../m1, /m2, ...: PointStamped or "
          "PoseStamped, marker_msg)", "best effort or reliable (qos), keep all",
          "the markers", when="mode measured"),
    Topic("sub", "bench/<bench>/identify (identify_topic)", "std_msgs/msg/Empty",
          "reliable, last 10", "identify what arrived so far", when="mode measured"),
)


class MeasuredIdentification:
    """The measured mode of ``node`` (an identification node with ``results_pub``)."""

    def __init__(self, node, params):
        self.node = node
        self.params = params
        self.live = MeasuredInputs(node, params)

    def inputs_ready(self):
        """The rig's topics have publishers (then /rig/ready goes out)."""
        return self.live.inputs_ready()

    def step(self, spinner):
        """Take what arrived; identify once asked (after draining every topic)."""
        spinner.spin_once(0.1)
        if not self.live.due():
            return
        spinner.spin_once(0)   # what arrived with the request
        try:
            self.identify()
        except MotoflexError as exc:   # a live rig may still send what is missing
            if self.params["exit_when_done"]:
                raise
            self.node.get_logger().error(f"not identified yet: {exc}")

    def identify(self):
        """Identify what arrived, publish it, write ``result_file``."""
        bench = self.live.bench
        result = identify_measured(self.live.measurements(), bench).to_dict()
        measured = result.pop("measured")
        summary = {"frames": measured["frames"], **measured["counts"],
                   "reference": measured["reference"], "messages": dict(self.live.received)}
        msg = DiagnosticArray(status=identification_statuses(
            bench.name, to_jsonable({**result, "measured": summary})))
        msg.header.stamp = self.node.get_clock().now().to_msg()
        self.node.results_pub.publish(msg)
        c = measured["counts"]
        self.node.get_logger().info(
            f"{bench.name}: identified from {measured['frames']} frames, k = "
            f"{result['static']['k']:.6g} N m/rad; dropped {c['dropped_marker_frames']} "
            f"marker frames, {c['dropped_load_samples']} load samples, unmatched "
            f"{c['unmatched_frames']}")
        if self.params["result_file"]:
            write_results(self.params["result_file"],
                          {bench.name: {**result, "measured": measured}})
        self.node.finished = self.params["exit_when_done"]
