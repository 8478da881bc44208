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
from motoflex_ros.nodes.cdr import points_from_cdr, wrench_vector_from_cdr
from motoflex_ros.units import NS_PER_S

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
            raise self.bad(ns, "header.stamp", f"{ns / NS_PER_S:.9f} s",
                           f"goes back from {self.last_ns / NS_PER_S:.9f} s (stamps must not "
                           f"decrease)")
        self.last_ns = ns

    def bad(self, ns, field, value, problem):
        return BadMessage(f"{self.name}: sample {self.count - 1} (stamp {ns / NS_PER_S:.9f} s): "
                          f"{field} = {value} {problem}; message refused, run stopped")


_WRENCH_FIELDS = ("force.x", "force.y", "force.z", "torque.x", "torque.y", "torque.z")


class BenchInputs:
    """Checked readers of one component's bench messages (serialized CDR, as the nodes take
    them); ``load_limit_n`` [N] is the largest |F_y| accepted, ``load_limit_nm`` [N m] the
    largest |M| (the moment tests'; 0: none); messages name the topic as resolved in the
    node's ``namespace`` (/bench/<c>/load, or /rig_a/bench/<c>/load)."""

    def __init__(self, component, load_limit_n, namespace="/", load_limit_nm=0.0):
        self.component = component
        self.load_limit_n = float(load_limit_n)
        self.load_limit_nm = float(load_limit_nm)
        self.prefix = namespace.rstrip("/") + "/"
        self._topics = {}

    @classmethod
    def of_plan(cls, component, plan, namespace="/"):
        """The readers of a component's campaign: the plan's load limits (CampaignPlan)."""
        return cls(component, plan.load_limit_n, namespace, plan.load_limit_nm)

    def _topic(self, leaf):
        name = self.prefix + topic(self.component, leaf)
        return self._topics.get(name) or self._topics.setdefault(name, _TopicCheck(name))

    def wrench(self, data):
        """(stamp [ns], (F_x, F_y, F_z, M_x, M_y, M_z) [N, N m]) of a /bench/<c>/load message,
        checked: finite, |F_y| and |M| within the protocol's range."""
        ns, values = wrench_vector_from_cdr(data)
        check = self._topic("load")
        check.next(ns)
        for name, value in zip(_WRENCH_FIELDS, values):
            if not math.isfinite(value):
                raise check.bad(ns, f"wrench.{name}", repr(value), "is not a finite number")
        force = values[1]
        if abs(force) > self.load_limit_n:
            raise check.bad(ns, "wrench.force.y", f"{force:.6g} N",
                            f"is beyond the protocol's range (|F_y| <= "
                            f"{self.load_limit_n:.6g} N)")
        moment = math.hypot(*values[3:])
        if moment > self.load_limit_nm:
            raise check.bad(ns, "wrench.torque", f"|M| = {moment:.6g} N m",
                            f"is beyond the protocol's range (|M| <= "
                            f"{self.load_limit_nm:.6g} N m)")
        return ns, values

    def load(self, data):
        """(stamp [ns], F_y [N]) of a /bench/<c>/load message, checked as :meth:`wrench`."""
        ns, values = self.wrench(data)
        return ns, values[1]

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
