"""Load actuator: plays a planned campaign as a stream of load samples with phase labels.

Load histories (F_y at the loaded end [N], t [s] from the test's start):

- static: cosine ramp F = F_st (1 - cos(pi t / T_r)) / 2 for t <= T_r (phase 'ramp'), then
  F_st (phase 'hold');
- harmonic / sweep: F = A e(t) sin(2 pi f t) with the onset envelope e = (1 - cos(pi t / T_on))
  / 2 for t < T_on (no derivative jump at the start), 1 after; phase 'onset' until the reading
  starts (T_read >= T_on, longer at resonance, see :func:`motoflex_ros.bench.plan.onset_times`),
  'steady' after;
  the test runs until :meth:`LoadActuator.end_test` is called (the identifier found the
  running mean settled) or its maximum duration;
- decay: the first sample holds the preload (phase 'preload': the structure starts from static
  equilibrium under it), then F = 0 (phase 'release').

A test's load is the wrench ``force`` x ``wrench`` at the loaded end: ``wrench`` the unit wrench
(F_x, F_y, F_z, M_x, M_y, M_z) of the test (:data:`LATERAL_WRENCH` for the paper's tests, a
unit moment for the moment tests of the principal hinges), ``force`` its amplitude [N or N m].

Tests follow each other with a pause of ``PAUSE_S`` so that time keeps increasing.
"""
import math
from dataclasses import dataclass, fields

__all__ = ["LoadSample", "LoadActuator", "test_forces", "PAUSE_S", "LATERAL_WRENCH",
           "wrench_amplitude"]

PAUSE_S = 0.1
LATERAL_WRENCH = (0.0, 1.0, 0.0, 0.0, 0.0, 0.0)
"""Unit wrench of the paper's tests: F_y at the loaded end."""


def wrench_amplitude(unit, wrench):
    """Amplitude a [N or N m] of a wrench (6,) along the unit wrench ``unit``: u . w (exactly
    F_y for the lateral unit wrench).

    >>> wrench_amplitude(LATERAL_WRENCH, (0.0, -12.5, 0.0, 0.0, 0.0, 0.0))
    -12.5
    """
    return float(sum(u * w for u, w in zip(unit, wrench)))


@dataclass(frozen=True)
class LoadSample:
    """One commanded load: sample index, time t [s], sample period dt [s], force F_y [N] (the
    amplitude [N or N m] of ``wrench``), the test name and kind, its phase, frequency [Hz] (0
    if none), whether it starts a test and the test's unit wrench at q0 (default F_y)."""

    index: int
    t: float
    dt: float
    force: float
    test: str
    kind: str
    phase: str
    frequency_hz: float
    test_start: bool
    wrench: tuple = LATERAL_WRENCH

    def __post_init__(self):
        if self.wrench is not LATERAL_WRENCH:
            object.__setattr__(self, "wrench", tuple(float(v) for v in self.wrench))

    @property
    def wrench_vector(self):
        """The commanded wrench at q0, force x wrench [N, N m]."""
        return tuple(self.force * w for w in self.wrench)

    def to_dict(self):
        """Plain dict (for messages and files; the fields are plain values, so no deep copy
        as ``dataclasses.asdict`` makes: this runs once per sample of the graph). The wrench is
        left out when it is the lateral force (the paper's tests: their labels stay as
        before)."""
        out = {f.name: getattr(self, f.name) for f in fields(self)}
        if self.wrench == LATERAL_WRENCH:
            del out["wrench"]
        else:
            out["wrench"] = list(self.wrench)
        return out

    @classmethod
    def from_dict(cls, data):
        """Inverse of :meth:`to_dict`."""
        return cls(**data)


def _static_force(plan, t):
    if t < plan.ramp_time_s:
        return plan.amplitude_n * 0.5 * (1.0 - math.cos(math.pi * t / plan.ramp_time_s)), "ramp"
    return plan.amplitude_n, "hold"


def _harmonic_force(plan, t):
    eps = 1e-9 / plan.rate_hz
    envelope = 1.0
    if t < plan.onset_time_s - eps:
        envelope = 0.5 * (1.0 - math.cos(math.pi * t / plan.onset_time_s))
    phase = "onset" if t < plan.read_time_s - eps else "steady"
    return plan.amplitude_n * envelope * math.sin(2.0 * math.pi * plan.frequency_hz * t), phase


def _decay_force(plan, t):
    return (plan.amplitude_n, "preload") if t == 0.0 else (0.0, "release")


_FORCES = {"static": _static_force, "harmonic": _harmonic_force, "sweep": _harmonic_force,
           "decay": _decay_force}


def test_forces(plan, j):
    """Force [N] and phase of sample j of a test (t = j / rate_hz)."""
    return _FORCES[plan.kind](plan, j / plan.rate_hz)


class LoadActuator:
    """Stage object: ``next_sample()`` gives the campaign's samples one by one (None at the
    end); ``end_test(name)`` stops the running test if it is ``name``."""

    def __init__(self, campaign_plan):
        self.tests = list(campaign_plan.tests)
        self.index = 0
        self._test = -1
        self._j = 0
        self._t0 = 0.0
        self._last_t = -PAUSE_S

    def _start_next_test(self):
        self._test += 1
        self._j = 0
        self._t0 = self._last_t + PAUSE_S

    def next_sample(self):
        """The next LoadSample, or None when the campaign is over."""
        if self._test < 0 or self._j >= self.tests[self._test].max_samples:
            self._start_next_test()
        if self._test >= len(self.tests):
            return None
        plan = self.tests[self._test]
        force, phase = test_forces(plan, self._j)
        t = self._t0 + self._j / plan.rate_hz
        sample = LoadSample(self.index, t, 1.0 / plan.rate_hz, force, plan.name, plan.kind,
                            phase, plan.frequency_hz, self._j == 0, plan.wrench)
        self.index += 1
        self._j += 1
        self._last_t = t
        return sample

    def end_test(self, name):
        """Stop test ``name`` if it is running (its remaining samples are skipped)."""
        if 0 <= self._test < len(self.tests) and self.tests[self._test].name == name:
            self._j = self.tests[self._test].max_samples
