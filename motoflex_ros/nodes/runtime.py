"""Plumbing shared by every node: base class, fast message loop, gap detection, ``main``.

- :class:`RigNode` declares and validates the node's parameters (:mod:`.params`), turns on
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
- The messages are taken, published and spun through :mod:`.transport` (the ctypes path by
  default, plain rclpy with ``MOTOFLEX_TRANSPORT=rclpy``); :data:`FastSpinner` and
  :func:`publish_patiently` are its names of old.
- :func:`run_node` is every executable's ``main``: DDS on loopback unless MOTOFLEX_DDS=network
  (:mod:`motoflex_ros.nodes.dds`), ``rclpy.init`` reads ``--ros-args``
  (``-p``, ``--params-file``), SIGINT and SIGTERM end the loop cleanly (the node's
  :meth:`RigNode.close` runs), a parameter error prints one line and exits with 2;
  ``--help`` prints the node's parameters with their defaults and exits 0. A node with
  a job of its own to finish (``ENDS_ITSELF``: a pacer, the vehicle simulator) that a signal
  stops before it finished exits with 128 + the signal's number, so that nobody takes its end
  for the end of the run; a node that serves until it is stopped (the recorder) exits 0.
"""
import importlib
import os
import signal
import sys
import time

import rclpy
from diagnostic_msgs.msg import KeyValue
from rclpy.impl.implementation_singleton import rclpy_implementation
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
from rclpy.signals import SignalHandlerOptions
from std_msgs.msg import String

from motoflex_ros.errors import MotoflexError
from motoflex_ros.nodes.dds import configure_dds
from motoflex_ros.nodes.endpoints import InputGuard, RunEndpoints
from motoflex_ros.nodes.interfaces import topics_help
from motoflex_ros.nodes.params import declare_parameters, parameters_help
from motoflex_ros.nodes.transport import publish_patiently, publisher_gid, selected, spinner

__all__ = ["RigNode", "FastSpinner", "run_node", "print_help", "publish_patiently",
           "message_class",
           "reliable_qos",
           "latched_qos", "READY_TOPIC", "ACK_TOPIC", "PROGRESS_TOPIC", "GAP_EXIT_CODE"]

READY_TOPIC = "rig/ready"   # relative: under the node's namespace
MATCH_TIMEOUT_S = 5.0  # longest wait for the publishers' side of discovery [s]
READY_HOLD_S = 0.3  # inputs must have been ready this long before /rig/ready [s]
GAP_EXIT_CODE = 3  # a node that saw a sequence gap exits with this code
ACK_TOPIC = "rig/ack"
PROGRESS_TOPIC = "rig/progress"   # KeyValue: component, tests it finished (a few a run)


def message_class(type_name):
    """The rclpy message class of 'pkg/msg/Type'."""
    package, _, name = type_name.split("/")
    return getattr(importlib.import_module(f"{package}.msg"), name)


def reliable_qos():
    """Reliable, keep-all, volatile: nothing is dropped, the writer waits for the reader."""
    return QoSProfile(depth=1, history=HistoryPolicy.KEEP_ALL,
                      reliability=ReliabilityPolicy.RELIABLE,
                      durability=DurabilityPolicy.VOLATILE)


def latched_qos(depth=100):
    """Reliable, transient-local: late subscribers get the last ``depth`` messages."""
    return QoSProfile(depth=depth, history=HistoryPolicy.KEEP_LAST,
                      reliability=ReliabilityPolicy.RELIABLE,
                      durability=DurabilityPolicy.TRANSIENT_LOCAL)


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


FastSpinner = spinner   # the name nodes/launcher used before nodes/transport.py


def _profiler():
    """A running cProfile.Profile if MOTOFLEX_PROFILE names a directory (development aid; the
    node's start-up, imports and set-up, included)."""
    if not os.environ.get("MOTOFLEX_PROFILE"):
        return None
    import cProfile
    profile = cProfile.Profile()
    profile.enable()
    return profile


def _dump_profile(profile, name):
    """Write ``<name>.prof`` and ``<name>.cpu.json`` (the whole process's CPU seconds, all
    threads, from ``resource.getrusage``) to $MOTOFLEX_PROFILE."""
    import json
    import resource
    profile.disable()
    folder = os.environ["MOTOFLEX_PROFILE"]
    profile.dump_stats(f"{folder}/{name}.prof")
    usage = resource.getrusage(resource.RUSAGE_SELF)
    with open(f"{folder}/{name}.cpu.json", "w") as out:
        json.dump({"user_s": usage.ru_utime, "system_s": usage.ru_stime,
                   "main_thread_s": time.thread_time()}, out)


def _deliver_everything(node, timeout_s=30.0):
    """Before a node that finished exits: wait until every reader acknowledged every message
    (a reliable writer that dies with unacknowledged data loses it, silently, at the end).
    """
    from rclpy.duration import Duration
    for publisher in node.publishers:
        if not publisher.wait_for_all_acked(Duration(seconds=timeout_s)):
            node.get_logger().error(f"{publisher.topic_name}: readers did not acknowledge "
                                    f"everything within {timeout_s:g} s")


def _params_files(args):
    """The files after each --params-file among the ROS arguments."""
    return [args[i + 1] for i, arg in enumerate(args[:-1]) if arg == "--params-file"]


def _init_ros(args):
    """``rclpy.init``, after checking each --params-file as the config loader checks a file
    (missing, not text, not YAML, a key twice: ConfigError naming file and key); anything else
    rcl refuses (e.g. a bad ``-p`` value) is a MotoflexError with rcl's message, not an
    RCLError traceback."""
    from motoflex_ros.config import load_yaml
    from motoflex_ros.errors import ConfigError
    for path in _params_files(sys.argv if args is None else list(args)):
        if not isinstance(load_yaml(path), dict):
            raise ConfigError(path, "", "expected a mapping {node name: {ros__parameters: "
                                        "{name: value}}}")
    try:
        rclpy.init(args=args, signal_handler_options=SignalHandlerOptions.NO)
    except rclpy_implementation.RCLError as exc:
        rclpy.try_shutdown()
        message = str(exc).split(", at ")[0]   # rcl appends the C source locations
        raise MotoflexError(f"cannot read the ROS arguments: {message}") from None


def _unknown_arguments(args):
    """A MotoflexError for command-line words outside ``--ros-args`` (a node takes none but
    --help: ``identification --params-file p.yaml`` would otherwise run with its defaults)."""
    from rclpy.utilities import remove_ros_args
    try:
        words = remove_ros_args(sys.argv if args is None else list(args))[1:]
    except rclpy_implementation.RCLError:
        return None   # ROS arguments rcl cannot parse: _init_ros says what is wrong
    if words:
        return MotoflexError(f"unknown argument '{words[0]}' (a node takes its settings "
                             f"after --ros-args: --ros-args -p NAME:=VALUE or --params-file "
                             f"FILE; --help lists them)")
    return None


def _help_asked(args):
    """Does the command line (not its ROS arguments) ask for -h / --help? (ROS arguments rcl
    cannot parse, e.g. a missing --params-file, are reported by :func:`_init_ros`.)"""
    from rclpy.utilities import remove_ros_args
    try:
        return not {"-h", "--help"}.isdisjoint(remove_ros_args(args)[1:])
    except rclpy_implementation.RCLError:
        return False


def print_help(node_class):
    """What ``node_class`` does (its module's summary), its topics and its parameters, on
    stdout."""
    summary = (sys.modules[node_class.__module__].__doc__ or "").strip().split("\n\n")[0]
    print(f"usage: {node_class.NAME} [--help] [--ros-args [-p NAME:=VALUE]... "
          f"[--params-file FILE]]\n\n{summary}\n\ntopics (relative: under the node's "
          "namespace; {c}: each component; type [QoS]: meaning):",
          *topics_help(node_class.TOPICS),
          "\nparameters (type and range, default: meaning):",
          *parameters_help(node_class.PARAMS), sep="\n")


def _refuse(node_class, exc):
    """A user error before the loop: one line on stderr, exit code 2."""
    print(f"{node_class.NAME}: error: {exc}", file=sys.stderr)
    return 2


_SIGNAL_NAMES = ("SIGINT", "SIGTERM")


def run_node(node_class, args=None):
    """Run ``node_class`` until it finishes or gets SIGINT/SIGTERM; returns the exit code."""
    if _help_asked(args):
        print_help(node_class)
        return 0
    stop = []
    profile = _profiler()
    try:
        configure_dds(os.environ)   # loopback unless MOTOFLEX_DDS=network (before rclpy.init)
        unknown = _unknown_arguments(args)
        if unknown is not None:
            raise unknown
        selected()   # the transport's switch and, on the ctypes path, its versions
        _init_ros(args)
    except MotoflexError as exc:
        return _refuse(node_class, exc)
    for signum in (signal.Signals[n] for n in _SIGNAL_NAMES):
        signal.signal(signum, lambda num, _frame: stop.append(signal.Signals(num).name))
    try:
        node = node_class()
    except MotoflexError as exc:
        rclpy.try_shutdown()
        return _refuse(node_class, exc)
    node_spinner = spinner(node)
    launcher = os.environ.get("MOTOFLEX_PARENT_PID")
    try:
        while not stop and not node.finished:
            node.announce_ready()   # every node, pacers too (the launcher waits for all)
            node.step(node_spinner)
            if launcher and os.getppid() != int(launcher):
                stop.append("launcher gone")   # the motoflex process that started us died
    except MotoflexError as exc:
        node.get_logger().error(str(exc))
        node.exit_code = 2
    finally:
        if node.finished:
            _deliver_everything(node)
        reason = stop[0] if stop else "finished"
        if stop:
            node.get_logger().info(f"stopped by {reason}")
            if node.ENDS_ITSELF and reason in _SIGNAL_NAMES and not node.exit_code:
                node.exit_code = 128 + signal.Signals[reason].value
        node.close(reason)
        name = node.get_name()
        node.destroy_node()
        rclpy.try_shutdown()
        if profile is not None:
            _dump_profile(profile, name)
    return node.exit_code
