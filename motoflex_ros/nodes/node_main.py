"""Every executable's ``main``: :func:`run_node` starts a node, runs its loop, ends it cleanly.

DDS on loopback unless MOTOFLEX_DDS=network (:mod:`motoflex_ros.nodes.dds`), the transport
checked (:func:`.transport.selected`), ``rclpy.init`` reads ``--ros-args`` (``-p``,
``--params-file``; :mod:`.node_command_line`), SIGINT and SIGTERM end the loop cleanly (the
node's :meth:`.rig_node.RigNode.close` runs), a parameter error prints one line and exits with
2; ``--help`` prints the node's parameters with their defaults and exits 0. A node with a job
of its own to finish (``ENDS_ITSELF``: a pacer, the vehicle simulator) that a signal stops
before it finished exits with 128 + the signal's number, so that nobody takes its end for the
end of the run; a node that serves until it is stopped (the recorder) exits 0. A node that
finished waits until its readers acknowledged everything it published before it exits.
"""
import cProfile
import json
import os
import resource
import signal
import sys
import time

import rclpy
from rclpy.duration import Duration

from motoflex_ros.errors import MotoflexError
from motoflex_ros.nodes.dds import configure_dds
from motoflex_ros.nodes.node_command_line import (
    help_asked,
    init_ros,
    print_help,
    unknown_arguments,
)
from motoflex_ros.nodes.transport import selected, spinner

__all__ = ["run_node"]


def _profiler():
    """A running cProfile.Profile if MOTOFLEX_PROFILE names a directory (development aid; the
    node's start-up, imports and set-up, included)."""
    if not os.environ.get("MOTOFLEX_PROFILE"):
        return None
    profile = cProfile.Profile()
    profile.enable()
    return profile


def _dump_profile(profile, name):
    """Write ``<name>.prof`` and ``<name>.cpu.json`` (the whole process's CPU seconds, all
    threads, from ``resource.getrusage``) to $MOTOFLEX_PROFILE."""
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
    for publisher in node.publishers:
        if not publisher.wait_for_all_acked(Duration(seconds=timeout_s)):
            node.get_logger().error(f"{publisher.topic_name}: readers did not acknowledge "
                                    f"everything within {timeout_s:g} s")


def _refuse(node_class, exc):
    """A user error before the loop: one line on stderr, exit code 2."""
    print(f"{node_class.NAME}: error: {exc}", file=sys.stderr)
    return 2


_SIGNAL_NAMES = ("SIGINT", "SIGTERM")


def run_node(node_class, args=None):
    """Run ``node_class`` until it finishes or gets SIGINT/SIGTERM; returns the exit code."""
    if help_asked(args):
        print_help(node_class)
        return 0
    stop = []
    profile = _profiler()
    try:
        configure_dds(os.environ)   # loopback unless MOTOFLEX_DDS=network (before rclpy.init)
        unknown = unknown_arguments(args)
        if unknown is not None:
            raise unknown
        selected()   # the transport's switch and, on the ctypes path, its versions
        init_ros(args)
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
