"""The campaign process's own node: sees nodes come up, follows /clock, collects results."""
import time

from diagnostic_msgs.msg import KeyValue
from rclpy.node import Node
from rosgraph_msgs.msg import Clock
from std_msgs.msg import String

from motoflex_ros.launcher.graph import NodeDied
from motoflex_ros.launcher.interrupts import raise_if_interrupted
from motoflex_ros.launcher.run_failures import pacer_failed, peer_room_problem
from motoflex_ros.nodes.endpoints import GraphWatch, InputGuard
from motoflex_ros.nodes.interfaces import PROGRESS_TOPIC, READY_TOPIC
from motoflex_ros.nodes.qos_profiles import latched_qos
from motoflex_ros.nodes.stamps import time_ns
from motoflex_ros.nodes.transport import spinner
from motoflex_ros.progress import progress_bar
from motoflex_ros.units import NS_PER_S

__all__ = ["Monitor"]


class Monitor(Node):
    """Watches a running graph from the launching process."""

    def __init__(self, context, names, collect=(), endpoints=None, namespace="/"):
        super().__init__("motoflex_monitor", context=context, namespace=namespace)
        # the run's own publishers only (a foreign /clock, results...); no gap count: the
        # progress subscription keeps only the last /clock
        self.guard = InputGuard(self, endpoints, count_gaps=lambda sub: False)
        self.graph_watch = GraphWatch(self, endpoints)
        self.names = frozenset(names)
        self.ready = set()
        self.sim_ns = 0
        self.tests_done = {}   # component: tests finished (the load actuator's rig/progress)
        self.collected = {topic: [] for topic, _ in collect}
        self.create_subscription(String, READY_TOPIC, lambda m: self.ready.add(m.data),
                                 latched_qos())
        self.create_subscription(Clock, "clock", self._on_clock, 1)  # progress only
        self.create_subscription(KeyValue, PROGRESS_TOPIC, self._on_progress, 10)
        for topic, msg_type in collect:
            self.create_subscription(msg_type, topic, self.collected[topic].append,
                                     latched_qos())
        self.spinner = spinner(self)

    def spin(self, timeout_s):
        """Handle what arrives within ``timeout_s`` [s] (the count); look for foreign
        publishers in the graph now and then."""
        count = self.spinner.spin_once(timeout_s)
        raise_if_interrupted()   # SIGINT/SIGTERM noted meanwhile (launcher/interrupts.py)
        self.graph_watch.check()
        return count

    def _on_clock(self, msg):
        self.sim_ns = max(self.sim_ns, time_ns(msg.clock))

    def _on_progress(self, msg):
        self.tests_done[msg.key] = max(self.tests_done.get(msg.key, 0), int(msg.value))

    def wait_ready(self, graph, pacer, timeout, finishers=()):
        """Wait until every node announced itself on /rig/ready (or the pacer already ended).

        A finisher may legitimately be done before its ready message reached us (a fast
        replay): one that exited 0 counts as up, and is not a death.
        """
        deadline = time.monotonic() + timeout
        while pacer not in graph.exited():
            done = _finished(graph, finishers)
            if self.names <= self.ready | set(done):
                return
            graph.check_alive(allowed=(pacer, *done))
            if time.monotonic() > deadline:
                missing = ", ".join(sorted(self.names - self.ready))
                full = peer_room_problem(graph.domain_id)   # joined by others meanwhile?
                raise NodeDied(f"nodes not up after {timeout:g} s: {missing}"
                               + (f"; likely cause: {full}" if full else ""))
            self.spin(0.1)

    def follow(self, graph, pacer, duration_s, progress, finishers=(), tests_total=None):
        """Spin until the pacing node exits. The progress bar counts the bench tests finished
        out of ``tests_total`` (a campaign: a test settles at a time no one knows before, so
        simulated time has no fixed total), else simulated time out of ``duration_s`` [s]
        (a replay: the bag's duration)."""
        bar = _progress_bar(duration_s, tests_total) if progress else None
        try:
            while True:
                self.spin(0.1)
                if bar is not None:
                    self._show(bar, tests_total)
                code = graph.exited().get(pacer)
                if code is not None:
                    if code != 0:   # a worker that died first is the cause: name it
                        graph.check_alive(allowed=(pacer, *_finished(graph, finishers)))
                        raise pacer_failed(graph, pacer, code)
                    if bar is not None:   # done: a replay's last /clock may lie short of it
                        bar.update(bar.total - bar.n)
                    return
                graph.check_alive(allowed=(pacer, *_finished(graph, finishers)))
        finally:
            if bar is not None:
                bar.close()

    def _show(self, bar, tests_total):
        """Bring the bar to what the graph did (tests finished, or simulated time)."""
        if tests_total:
            done = min(sum(self.tests_done.values()), tests_total)
            bar.set_postfix_str(f"simulated {self.sim_ns / NS_PER_S:.1f} s", refresh=False)
        else:
            done = round(self.sim_ns / NS_PER_S, 3)
        if done != bar.n:
            bar.update(done - bar.n)
        elif tests_total:
            bar.refresh()   # the simulated time moves between tests (a log: no new line)

    def wait_finishers(self, graph, done, timeout):
        """Wait until every node in ``done`` exited 0 (the pacer first, then the finishers)."""
        deadline = time.monotonic() + timeout
        while True:
            exited = graph.exited()
            for name in done:
                if exited.get(name) not in (None, 0):
                    raise pacer_failed(graph, name, exited[name])
            if all(name in exited for name in done):
                return
            if time.monotonic() > deadline:
                late = ", ".join(n for n in done if n not in exited)
                raise NodeDied(f"nodes not finished after {timeout:g} s: {late}")
            graph.check_alive(allowed=done)
            self.spin(0.1)

    def drain(self, graph, done, timeout):
        """Handle what is still in flight after the run ended (short quiet period)."""
        deadline = time.monotonic() + timeout
        quiet = 0
        while quiet < 3 and time.monotonic() < deadline:
            quiet = quiet + 1 if self.spin(0.1) == 0 else 0
            graph.check_alive(allowed=done)


def _finished(graph, names):
    """Those of ``names`` that already exited 0."""
    exited = graph.exited()
    return tuple(n for n in names if exited.get(n) == 0)


def _progress_bar(duration_s, tests_total):
    if tests_total:
        return progress_bar(total=tests_total, unit="test", desc="campaign",
                            bar_format="{desc}: {percentage:3.0f}%|{bar}| {n}/{total} tests"
                                       "{postfix} [{elapsed}<{remaining}]")
    return progress_bar(total=round(duration_s, 3), unit="sim s", desc="replay",
                        bar_format="{desc}: {percentage:3.0f}%|{bar}| {n:.2f}/{total:.2f} "
                                   "sim s [{elapsed}<{remaining}]")
