"""The launcher's wait for nodes: a finisher that is already done is not a death.

Seen in CI: a fast ``motoflex replay --identify`` had the identification node finish and exit 0
before its /rig/ready message reached the monitor, and the run was reported as "died (exit 0)".
"""
from types import SimpleNamespace

import pytest

pytest.importorskip("rclpy")
from motoflex_ros.launcher.graph import NodeDied  # noqa: E402
from motoflex_ros.launcher.monitor import Monitor  # noqa: E402


class FakeGraph:
    """Exit codes appear after a number of polls, like processes ending."""

    domain_id = 232   # the largest ROS domain id: no DDS participant of this machine in it

    def __init__(self, ends):
        self.ends = ends      # name -> (poll at which it exits, exit code)
        self.polls = 0

    def exited(self):
        self.polls += 1
        return {n: code for n, (at, code) in self.ends.items() if self.polls >= at}

    def check_alive(self, allowed=()):
        for name, code in self.exited().items():
            if name not in allowed:
                raise NodeDied(f"node '{name}' died (exit {code})")


def _monitor(ready):
    return SimpleNamespace(names=frozenset({"identification", "bag_replay"}), ready=set(ready),
                           spin=lambda timeout: 0)


def test_finisher_done_before_its_ready_message_counts_as_up():
    graph = FakeGraph({"identification": (1, 0)})
    Monitor.wait_ready(_monitor({"bag_replay"}), graph, "bag_replay", 5.0,
                       finishers=("identification",))


def test_finisher_that_failed_before_ready_is_a_death():
    graph = FakeGraph({"identification": (1, 1)})
    with pytest.raises(NodeDied, match="identification"):
        Monitor.wait_ready(_monitor({"bag_replay"}), graph, "bag_replay", 5.0,
                           finishers=("identification",))


def test_non_finisher_that_exits_0_before_ready_is_a_death():
    graph = FakeGraph({"identification": (1, 0)})
    with pytest.raises(NodeDied, match="identification"):
        Monitor.wait_ready(_monitor({"bag_replay"}), graph, "bag_replay", 5.0)


def test_missing_node_times_out_with_its_name():
    graph = FakeGraph({})
    with pytest.raises(NodeDied, match="not up after .* identification"):
        Monitor.wait_ready(_monitor({"bag_replay"}), graph, "bag_replay", 0.0,
                           finishers=("identification",))
