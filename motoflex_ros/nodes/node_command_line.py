"""A node's command line before it starts: ``--help``, words outside ``--ros-args``, and
``rclpy.init`` with its params files checked first.

A node takes its settings after ``--ros-args`` only (``-p NAME:=VALUE``, ``--params-file
FILE``; :mod:`.ros_args` reads what they give it). Anything else on its command line but
``-h``/``--help`` is refused with one line, as is a params file the config loader refuses and
whatever rcl refuses, instead of a traceback (:func:`.node_main.run_node` prints the line and
exits with 2).
"""
import sys

import rclpy
from rclpy.impl.implementation_singleton import rclpy_implementation
from rclpy.signals import SignalHandlerOptions
from rclpy.utilities import remove_ros_args

from motoflex_ros.config import load_yaml
from motoflex_ros.errors import ConfigError, MotoflexError
from motoflex_ros.nodes.interfaces import topics_help
from motoflex_ros.nodes.params import parameters_help
from motoflex_ros.nodes.ros_args import params_files

__all__ = ["help_asked", "print_help", "unknown_arguments", "init_ros"]


def init_ros(args):
    """``rclpy.init``, after checking each --params-file as the config loader checks a file
    (missing, not text, not YAML, a key twice: ConfigError naming file and key); anything else
    rcl refuses (e.g. a bad ``-p`` value) is a MotoflexError with rcl's message, not an
    RCLError traceback."""
    for path in params_files(sys.argv if args is None else list(args)):
        if not isinstance(load_yaml(path), dict):
            raise ConfigError(path, "", "expected a mapping {node name: {ros__parameters: "
                                        "{name: value}}}")
    try:
        rclpy.init(args=args, signal_handler_options=SignalHandlerOptions.NO)
    except rclpy_implementation.RCLError as exc:
        rclpy.try_shutdown()
        message = str(exc).split(", at ")[0]   # rcl appends the C source locations
        raise MotoflexError(f"cannot read the ROS arguments: {message}") from None


def unknown_arguments(args):
    """A MotoflexError for command-line words outside ``--ros-args`` (a node takes none but
    --help: ``identification --params-file p.yaml`` would otherwise run with its defaults)."""
    try:
        words = remove_ros_args(sys.argv if args is None else list(args))[1:]
    except rclpy_implementation.RCLError:
        return None   # ROS arguments rcl cannot parse: init_ros says what is wrong
    if words:
        return MotoflexError(f"unknown argument '{words[0]}' (a node takes its settings "
                             f"after --ros-args: --ros-args -p NAME:=VALUE or --params-file "
                             f"FILE; --help lists them)")
    return None


def help_asked(args):
    """Does the command line (not its ROS arguments) ask for -h / --help? (ROS arguments rcl
    cannot parse, e.g. a missing --params-file, are reported by :func:`init_ros`.)"""
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
