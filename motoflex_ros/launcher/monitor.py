"""The campaign process's own node: sees nodes come up, follows /clock, collects results."""
import time

from rclpy.node import Node
from rosgraph_msgs.msg import Clock
from std_msgs.msg import String

from motoflex_ros.launcher.graph import NodeDied
from motoflex_ros.launcher.interrupts import raise_if_interrupted
from motoflex_ros.nodes.conversions import time_ns
from motoflex_ros.nodes.endpoints import GraphWatch, InputGuard
from motoflex_ros.nodes.runtime import READY_TOPIC, FastSpinner, latched_qos

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
        self.collected = {topic: [] for topic, _ in collect}
        self.create_subscription(String, READY_TOPIC, lambda m: self.ready.add(m.data),
                                 latched_qos())
        self.create_subscription(Clock, "clock", self._on_clock, 1)  # progress only
        for topic, msg_type in collect:
            self.create_subscription(msg_type, topic, self.collected[topic].append,
                                     latched_qos())
        self.spinner = FastSpinner(self)

    def spin(self, timeout_s):
        """Handle what arrives within ``timeout_s`` [s] (the count); look for foreign
        publishers in the graph now and then."""
        count = self.spinner.spin_once(timeout_s)
        raise_if_interrupted()   # SIGINT/SIGTERM noted meanwhile (launcher/interrupts.py)
        self.graph_watch.check()
        return count

    def _on_clock(self, msg):
        self.sim_ns = max(self.sim_ns, time_ns(msg.clock))

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
                from motoflex_ros.launcher.run import peer_room_problem
                missing = ", ".join(sorted(self.names - self.ready))
                full = peer_room_problem(graph.domain_id)   # joined by others meanwhile?
                raise NodeDied(f"nodes not up after {timeout:g} s: {missing}"
                               + (f"; likely cause: {full}" if full else ""))
            self.spin(0.1)

    def follow(self, graph, pacer, duration_s, progress, finishers=()):
        """Spin until the pacing node exits; a progress bar over simulated time."""
        from motoflex_ros.launcher.run import pacer_failed
        bar = _progress_bar(duration_s) if progress else None
        try:
            while True:
                self.spin(0.1)
                if bar is not None:
                    bar.update(round(self.sim_ns / 1e9, 3) - bar.n)
                code = graph.exited().get(pacer)
                if code is not None:
                    if code != 0:   # a worker that died first is the cause: name it
                        graph.check_alive(allowed=(pacer, *_finished(graph, finishers)))
                        raise pacer_failed(graph, pacer, code)
                    if bar is not None:
                        bar.total = bar.n  # tests settle before their planned maximum
                    return
                graph.check_alive(allowed=(pacer, *_finished(graph, finishers)))
        finally:
            if bar is not None:
                bar.close()

    def wait_finishers(self, graph, done, timeout):
        """Wait until every node in ``done`` exited 0 (the pacer first, then the finishers)."""
        from motoflex_ros.launcher.run import pacer_failed
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


def _progress_bar(duration_s):
    from tqdm import tqdm
    return tqdm(total=round(duration_s, 3), unit="sim s", desc="campaign",
                # the total is the protocol's longest plan: tests that settle sooner end the
                # run earlier (the bar then jumps to its end), hence "at most"
                bar_format="{desc}: {percentage:3.0f}%|{bar}| {n:.2f} sim s of at most "
                           "{total:.2f} [{elapsed}<{remaining}]")
