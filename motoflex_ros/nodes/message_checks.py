"""The values of the bench's messages, checked by the first node that reads them.

A NaN or infinite load or marker coordinate, a stamp earlier than the one before on the same
topic, or a load beyond the protocol's range (:attr:`CampaignPlan.load_limit_n
<motoflex_ros.bench.plan.CampaignPlan.load_limit_n>`) raises :class:`BadMessage` naming the
topic, the field and the sample (its index on the topic and its stamp): the node stops with
that line and the run fails at once, instead of feeding the core numbers it cannot use (an
"SVD did not converge" traceback, or a stall until the actuator's acknowledgement timeout).
"""
import math

import numpy as np

from motoflex_ros.errors import MotoflexError
from motoflex_ros.nodes.bench_graph import topic
from motoflex_ros.nodes.conversions import points_from_cdr, wrench_from_cdr

__all__ = ["BadMessage", "BenchInputs"]

_AXES = "xyz"


class BadMessage(MotoflexError):
    """A message carries a value the rig cannot use."""


class _TopicCheck:
    """Sample count and last stamp of one topic."""

    def __init__(self, name):
        self.name = name
        self.count = 0
        self.last_ns = None

    def next(self, ns):
        """Count a message stamped ``ns`` [ns]; raise if the stamp goes back."""
        self.count += 1
        if self.last_ns is not None and ns < self.last_ns:
            raise self.bad(ns, "header.stamp", f"{ns / 1e9:.9f} s",
                           f"goes back from {self.last_ns / 1e9:.9f} s (stamps must not "
                           f"decrease)")
        self.last_ns = ns

    def bad(self, ns, field, value, problem):
        return BadMessage(f"{self.name}: sample {self.count - 1} (stamp {ns / 1e9:.9f} s): "
                          f"{field} = {value} {problem}; message refused, run stopped")


class BenchInputs:
    """Checked readers of one component's bench messages (serialized CDR, as the nodes take
    them); ``load_limit_n`` [N] is the largest |F_y| accepted; messages name the topic as
    resolved in the node's ``namespace`` (/bench/<c>/load, or /rig_a/bench/<c>/load)."""

    def __init__(self, component, load_limit_n, namespace="/"):
        self.component = component
        self.load_limit_n = float(load_limit_n)
        self.prefix = namespace.rstrip("/") + "/"
        self._topics = {}

    def _topic(self, leaf):
        name = self.prefix + topic(self.component, leaf)
        return self._topics.get(name) or self._topics.setdefault(name, _TopicCheck(name))

    def load(self, data):
        """(stamp [ns], F_y [N]) of a /bench/<c>/load message, checked."""
        ns, force = wrench_from_cdr(data)
        check = self._topic("load")
        check.next(ns)
        if not math.isfinite(force):
            raise check.bad(ns, "wrench.force.y", repr(force), "is not a finite number")
        if abs(force) > self.load_limit_n:
            raise check.bad(ns, "wrench.force.y", f"{force:.6g} N",
                            f"is beyond the protocol's range (|F_y| <= "
                            f"{self.load_limit_n:.6g} N)")
        return ns, force

    def markers(self, leaf, data):
        """(stamp [ns], points (n, 3) [m]) of a /bench/<c>/<leaf> PoseArray, checked."""
        ns, points = points_from_cdr(data)
        check = self._topic(leaf)
        check.next(ns)
        bad = np.argwhere(~np.isfinite(points))
        if len(bad):
            i, axis = bad[0]
            raise check.bad(ns, f"poses[{i}].position.{_AXES[axis]}", repr(float(points[i, axis])),
                            "is not a finite number")
        return ns, points
