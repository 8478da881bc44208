"""Run a node graph to its end: start, wait until every node is up, show progress, stop.

The run ends when the pacing node (``sim_clock``, or ``bag_replay``) exits 0. A node that dies,
a pacing node that fails, SIGINT or SIGTERM stop every node (recorder last, so that it finishes
the bag) and raise :class:`RunFailed` / :class:`RunInterrupted` naming what happened. The run's
ROS_DOMAIN_ID (``ROS_DOMAIN_ID`` if set, else a free one: :mod:`.domain`) and DDS transport
(:mod:`.dds`) are printed on stderr at the start.
"""
import os
import shutil
import sys
import tempfile
import time
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path

import rclpy
from rclpy.signals import SignalHandlerOptions

from motoflex_ros.errors import MotoflexError
from motoflex_ros.input_pins import InputChanged, check_pins
from motoflex_ros.launcher.domain import DomainLock, requested_domain
from motoflex_ros.launcher.graph import NodeDied, NodeGraph, describe_exit
from motoflex_ros.launcher.interrupts import deferred_interrupts, raise_if_interrupted
from motoflex_ros.launcher.monitor import Monitor
from motoflex_ros.launcher.run_failures import RunFailed, check_peer_room
from motoflex_ros.nodes.dds import configure_dds
from motoflex_ros.nodes.endpoints import RunEndpoints
from motoflex_ros.nodes.transport import selected, selected_name

__all__ = ["RunInterrupted", "RunResult", "run_graph", "work_folder", "ros_log_home"]


class RunInterrupted(MotoflexError):
    """The run was stopped by SIGINT or SIGTERM."""


@dataclass(frozen=True)
class RunResult:
    """Outcome of a run: domain id, wall time [s], exit codes, and what the monitor saw."""

    domain_id: int
    wall_s: float
    exit_codes: dict
    collected: dict


def ros_log_home():
    """Where ROS keeps logs: $ROS_LOG_DIR, else $ROS_HOME/log, else ~/.ros/log."""
    if os.environ.get("ROS_LOG_DIR"):
        return Path(os.environ["ROS_LOG_DIR"])
    return Path(os.environ.get("ROS_HOME") or Path.home() / ".ros") / "log"


@contextmanager
def work_folder(prefix, given=None, keep_logs_in=None):
    """The folder of a run's node parameters and logs: ``given`` as it is, or a temporary
    folder (``prefix`` + random, in the system temp directory) removed when the run ends,
    also when it fails. On a failure (a MotoflexError) its logs are first copied to
    ``keep_logs_in``/log (default: a folder of the same name under :func:`ros_log_home`) and
    the error's message names them there."""
    if given is not None:
        yield Path(given)
        return
    folder = Path(tempfile.mkdtemp(prefix=prefix))
    try:
        yield folder
    except MotoflexError as exc:
        kept = Path(keep_logs_in) / "log" if keep_logs_in else ros_log_home() / folder.name
        _keep_logs(exc, folder / "log", kept)
        raise
    finally:
        shutil.rmtree(folder, ignore_errors=True)


def _keep_logs(exc, logs, kept):
    """Copy the folder ``logs`` to ``kept`` and point the message of ``exc`` there."""
    if not logs.is_dir() or not any(logs.iterdir()):
        return
    try:
        shutil.copytree(logs, kept, dirs_exist_ok=True)
        where = str(kept)
    except OSError:   # a full disk: the message still carries each failed node's last lines
        where = f"{kept} (copied only in part)"
    exc.args = tuple(a.replace(str(logs), where) if isinstance(a, str) else a
                     for a in exc.args)


READY_TIMEOUT_S = 180.0
"""How long the nodes may take to come up [s]: on a quiet machine a campaign's eight nodes are
up in 5-10 s; two campaigns at once beside other work on two cores took over 60 s (the
recorder, which subscribes once it has discovered each topic's publishers, last)."""


def run_graph(specs, pacer, duration_s, work_dir=None, collect=(), progress=False,
              ready_timeout=READY_TIMEOUT_S, drain_timeout=30.0, finishers=(),
              finish_timeout=300.0, namespace=None, tests_total=None, pins=None):
    """Run ``specs`` until ``pacer`` exits 0 (and then every node in ``finishers``); returns a
    :class:`RunResult`. ``collect``: (topic, msg_type) pairs whose messages the monitor keeps
    (topics relative to ``namespace``, where every node runs: None or '/' for the root).
    ``tests_total``: the bench tests the pacer plays (the progress bar counts them), else
    the progress bar runs over ``duration_s`` of simulated time.
    ``pins``: {absolute path: SHA-256} of the inputs the launcher read; the nodes check what
    they read against them, and a pinned file that changed before the run ended fails it.
    """
    work_dir = Path(work_dir or tempfile.mkdtemp(prefix="motoflex_run_"))
    start = time.monotonic()
    with deferred_interrupts():   # raised by the monitor's loop, not mid-deserialisation
        try:
            dds = configure_dds(os.environ)   # this process's monitor node; the nodes inherit it
            selected()   # the transport's switch and the ctypes path's ROS releases, checked
            with DomainLock(domain_id=requested_domain(os.environ), namespace=namespace) as lock:
                where = f", namespace {namespace}" if (namespace or "/").strip("/") else ""
                print(f"motoflex: ROS_DOMAIN_ID {lock.domain_id} ({lock.origin}){where}; {dds}; "
                      f"ROS transport {selected_name()}", file=sys.stderr, flush=True)
                check_peer_room(lock.domain_id, len(specs) + 1)   # the nodes + the monitor
                graph = NodeGraph(specs, lock.domain_id, work_dir, namespace, pins)
                try:
                    graph.start()   # inside the try: a failure half-way stops what started
                    collected = _monitor(graph, pacer, (duration_s, tests_total), collect,
                                         progress, ready_timeout,
                                         (finishers, finish_timeout, drain_timeout))
                except BaseException:
                    graph.stop()
                    raise
                codes = graph.stop()
                raise_if_interrupted()
                _check_exit_codes(graph, codes)
                check_pins(graph.pins)
        except KeyboardInterrupt as exc:
            what = str(exc) or "SIGINT"
            raise RunInterrupted(f"interrupted by {what}; every node stopped "
                                 f"(logs: {work_dir / 'log'})") from None
        except (NodeDied, InputChanged) as exc:
            raise RunFailed(str(exc)) from None
    return RunResult(lock.domain_id, time.monotonic() - start, codes, collected)


def _monitor(graph, pacer, planned, collect, progress, ready_timeout, ending):
    context = rclpy.Context()
    # no log file of this process in ~/.ros/log (the nodes' logs are the run's, in its folder)
    rclpy.init(args=["--ros-args", "--disable-external-lib-logs"], context=context,
               domain_id=graph.domain_id, signal_handler_options=SignalHandlerOptions.NO)
    try:
        monitor = Monitor(context, [s.name for s in graph.specs], collect,
                          RunEndpoints(graph.endpoints_dir), graph.namespace)
        finishers, finish_timeout, drain_timeout = ending
        monitor.wait_ready(graph, pacer, ready_timeout, finishers)
        duration_s, tests_total = planned
        monitor.follow(graph, pacer, duration_s, progress, finishers, tests_total)
        monitor.wait_finishers(graph, (pacer, *finishers), finish_timeout)
        monitor.drain(graph, (pacer, *finishers), drain_timeout)
        return monitor.collected
    finally:
        rclpy.try_shutdown(context=context)


def _check_exit_codes(graph, codes):
    """RunFailed if a node ended badly when stopped (e.g. exit 3: it saw lost messages)."""
    bad = {name: code for name, code in codes.items() if code != 0}
    if bad:
        name, code = next(iter(bad.items()))
        raise RunFailed(f"node '{name}' ended with {describe_exit(code)} at the end of the run "
                        f"(exit 3 means it saw lost messages); its log: "
                        f"{graph.log_dir / (name + '.log')}: {graph.log_tail(name)}")
