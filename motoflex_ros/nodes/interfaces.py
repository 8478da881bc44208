"""The topics of each node, declared beside its parameters (issue 24, point 8).

Each node class lists its ``TOPICS``: what it publishes and subscribes, with the message type,
the QoS and what it carries. ``--help`` prints them with the parameters, and
docs/ros-interfaces.md is written from them (tools/write_ros_interfaces.py);
test/test_node_interfaces.py starts every node in-process and holds each declaration to the
endpoints the node really creates. Names are relative (under the node's namespace, given as
from the root /); ``{c}`` stands for each component of the parameter ``components``.
"""
import importlib
from dataclasses import dataclass

__all__ = ["READY_TOPIC", "ACK_TOPIC", "PROGRESS_TOPIC", "message_class", "Topic", "RELIABLE",
           "LATCHED", "LATCHED_LAST", "SIM_TIME", "READY", "CLOCK_IN", "RIG_TOPICS",
           "PACER_TOPICS", "ACK_OUT", "TF_STATIC", "TF_DYNAMIC", "PHASE_IN", "LOAD_IN",
           "topics_help", "expand"]

RELIABLE = "reliable, keep all, volatile"
LATCHED = "reliable, transient local (latched), last 100"
LATCHED_LAST = "reliable, transient local (latched), last 1"
LATCHED_TF = "reliable, transient local (latched), last 1000"
SIM_TIME = "rclpy's time source (use_sim_time)"

READY_TOPIC = "rig/ready"   # relative: under the node's namespace
ACK_TOPIC = "rig/ack"
PROGRESS_TOPIC = "rig/progress"   # KeyValue: component, tests it finished (a few a run)


def message_class(type_name):
    """The rclpy message class of 'pkg/msg/Type' (a :class:`Topic`'s ``msg_type``)."""
    package, _, name = type_name.split("/")
    return getattr(importlib.import_module(f"{package}.msg"), name)


@dataclass(frozen=True)
class Topic:
    """One endpoint: ``direction`` 'pub' or 'sub', relative ``name`` ({c}: each component),
    ROS ``msg_type`` (pkg/msg/Type), ``qos`` and ``description``; ``when`` says when it
    exists if not from the start ('' = always)."""

    direction: str
    name: str
    msg_type: str
    qos: str
    description: str
    when: str = ""

    def names(self, components=()):
        """The topic names, one per component where the name has {c}, from the root."""
        if "{c}" in self.name:
            return [f"/{self.name.format(c=c)}" for c in components]
        return [f"/{self.name}"]


READY = Topic("pub", READY_TOPIC, "std_msgs/msg/String", LATCHED,
              "the node's name once its inputs see their publishers (the launcher waits for "
              "every node's)")
CLOCK_IN = Topic("sub", "clock", "rosgraph_msgs/msg/Clock", SIM_TIME,
                 "simulated time of the run (use_sim_time)")
RIG_TOPICS = (READY, CLOCK_IN)
PACER_TOPICS = (
    Topic("sub", READY_TOPIC, "std_msgs/msg/String", LATCHED,
          "which nodes are up: the first sample waits for every node of wait_for"),
    Topic("sub", ACK_TOPIC, "diagnostic_msgs/msg/KeyValue", RELIABLE,
          "acknowledgements (key: node, value: simulated time handled [ns]) that pace the run"),
)
ACK_OUT = Topic("pub", ACK_TOPIC, "diagnostic_msgs/msg/KeyValue", RELIABLE,
                "this node's acknowledgement: key its name, value the simulated time [ns] it "
                "handled (and 'settled TEST' / 'done')")

TF_STATIC = Topic("pub", "rig/tf_static", "geometry_msgs/msg/TransformStamped", LATCHED_TF,
                  "fixed frames, one transform a message (the recorder writes them as "
                  "/tf_static, tf2_msgs/msg/TFMessage)")
TF_DYNAMIC = Topic("pub", "rig/tf", "geometry_msgs/msg/TransformStamped", RELIABLE,
                   "moving frames, one transform a message (recorded as /tf)")
PHASE_IN = Topic("sub", "bench/{c}/phase", "std_msgs/msg/String", RELIABLE,
                 "the load actuator's sample phase (JSON): which test, which part of it")
LOAD_IN = Topic("sub", "bench/{c}/load", "geometry_msgs/msg/WrenchStamped", RELIABLE,
                "commanded load [N]")


def expand(topics, components=(), conditions=()):
    """{(direction, name from the root): msg_type} of the ``topics`` that exist from the
    start, or whose ``when`` is one of ``conditions``."""
    return {(t.direction, name): t.msg_type for t in topics if t.when in ("", *conditions)
            for name in t.names(components)}


def topics_help(topics):
    """Lines describing ``topics`` for ``--help``: direction, name, type, QoS, meaning."""
    lines = []
    for direction, title in (("pub", "publishes"), ("sub", "subscribes")):
        chosen = [t for t in topics if t.direction == direction]
        if chosen:
            lines.append(f"{title}:")
        for t in chosen:
            when = f"; {t.when}" if t.when else ""
            lines.append(f"  /{t.name}  {t.msg_type}  [{t.qos}{when}]: {t.description}")
    return lines
