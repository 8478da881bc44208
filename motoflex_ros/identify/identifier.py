"""Streaming identification: consumes (load sample, measured pose) one at a time.

The :class:`Identifier` is the last stage of a bench campaign. It recognises the tests and
their phases from the labels of the load samples and keeps, per test, only what the paper's
method reads (Sect. 4.2.1-4.2.2):

- static: the poses and loads of the 'hold' phase (the load at its maximum);
- harmonic and sweep: the 'steady' phase, one least-squares sine fit per period, two peak
  poses per period (:mod:`motoflex_ros.identify.peaks`), l, beta, b per peak and their running
  mean; :meth:`Identifier.add_measurement` returns the test name once the mean has settled, so
  the load actuator can stop the test;
- decay: the 'release' phase, analysed by the matrix pencil at the end.

Measurements are matched to their load sample by index, so sensor latency does not matter.
"""
import math
from dataclasses import dataclass

import numpy as np

from motoflex_ros.identify.decay import decay_poles
from motoflex_ros.identify.peaks import (
    RunningMean,
    axis_of_pose,
    fit_sine,
    joint_distance_from_arm,
    peak_poses,
)
from motoflex_ros.identify.uncertainty import mean_and_covariance, propagate

__all__ = ["StaticReading", "HarmonicReading", "DecayReading", "Identifier"]

MIN_FIT_SAMPLES = 4
PEAKS_PER_WINDOW = 2  # the maximum and the minimum of the fitted lateral displacement


@dataclass(frozen=True)
class StaticReading:
    """Hold phase of the static test: mean force [N], mean pose (q - q0, theta) [m, rad], the
    covariance of that mean and the number of samples."""

    force: float
    pose: np.ndarray
    cov: np.ndarray
    n_samples: int


@dataclass(frozen=True)
class HarmonicReading:
    """A harmonic test: frequency [Hz], per-peak (l [m], beta [rad], b [m]) rows, whether the
    running mean settled, and the number of samples in the steady phase."""

    name: str
    kind: str
    frequency_hz: float
    peaks: np.ndarray
    settled: bool
    n_samples: int
    length: float

    @property
    def n_peaks(self):
        """Number of peaks used."""
        return len(self.peaks)

    @property
    def n_windows(self):
        """Number of fitted windows (independent observations; two peaks each)."""
        return len(self.peaks) // PEAKS_PER_WINDOW

    def mean(self):
        """Mean axis (l, beta, b) over the peaks and its covariance.

        beta and b are averaged; l = L - b / sin(beta) follows from them (see
        :class:`motoflex_ros.identify.peaks.RunningMean`). The covariance of the mean comes from
        the scatter of the per-window means: the maximum and the minimum of one window share
        one sine fit, so their errors are correlated and they count as one observation. With a
        single window the covariance is NaN (no spread estimate, see ``n_windows``).
        """
        per_period = self.peaks[:, 1:].reshape(-1, PEAKS_PER_WINDOW, 2).mean(axis=1)
        mean, cov = mean_and_covariance(per_period)

        def axis(v):
            return np.array([joint_distance_from_arm(v[0], v[1], self.length), v[0], v[1]])

        steps = 1e-7 * np.maximum(np.abs(mean), 1e-6)
        return propagate(axis, mean, cov, steps)


@dataclass(frozen=True)
class DecayReading:
    """Free decay: poles found by the matrix pencil and the number of samples."""

    poles: tuple
    n_samples: int
    dt: float


class _Static:
    def __init__(self, sample, q0):
        self.forces, self.poses = [], []

    def add(self, sample, pose, tau):
        if sample.phase == "hold":
            self.forces.append(sample.force)
            self.poses.append(pose)

    def reading(self, name):
        mean, cov = mean_and_covariance(self.poses)
        return StaticReading(float(np.mean(self.forces)), mean, cov, len(self.poses))


class _Harmonic:
    def __init__(self, sample, q0, settings):
        self.q0, self.kind, self.f = q0, sample.kind, sample.frequency_hz
        per_period = 1.0 / (self.f * sample.dt)
        self.periods = max(1, math.ceil(MIN_FIT_SAMPLES / per_period - 1e-9))
        self.expected = int(self.periods * per_period + 1e-6)
        self.length = float(np.hypot(q0[0], q0[2]))
        self.mean = RunningMean(self.length, settings.band_length_m, settings.band_angle_rad,
                                settings.settle_peaks)
        self.window, self.taus, self.poses, self.n = None, [], [], 0

    def _close_window(self):
        if len(self.taus) >= max(self.expected, MIN_FIT_SAMPLES):
            c, a, s = fit_sine(np.array(self.taus), np.array(self.poses), 2 * np.pi * self.f)
            for pose in peak_poses(c, a, s):
                axis = axis_of_pose(pose, self.q0)
                self.mean.add(axis.l, axis.beta, axis.b)
        self.taus, self.poses = [], []

    def add(self, sample, pose, tau):
        if sample.phase != "steady":
            return
        window = math.floor(tau * self.f / self.periods + 1e-9)
        if window != self.window:
            self._close_window()
            self.window = window
        self.taus.append(tau)
        self.poses.append(pose)
        self.n += 1

    def reading(self, name):
        self._close_window()
        return HarmonicReading(name, self.kind, self.f, np.array(self.mean.values).reshape(-1, 3),
                               self.mean.settled, self.n, self.length)


class _Decay:
    def __init__(self, sample, q0):
        self.scale = np.r_[np.ones(3), np.full(3, np.linalg.norm(q0))]
        self.poses, self.dt = [], None

    def add(self, sample, pose, tau):
        if sample.phase == "release":
            self.poses.append(pose * self.scale)
            self.dt = sample.dt

    def reading(self, name):
        poles = decay_poles(np.array(self.poses), self.dt) if self.poses else []
        return DecayReading(tuple(poles), len(self.poses), self.dt)


class Identifier:
    """Stage object: ``add_load(sample)`` then ``add_measurement(measurement)`` per sample;
    ``readings()`` at the end. q0 [m] is the loaded end; ``settings`` the HarmonicSettings
    (tolerance bands and peaks for the settling test)."""

    def __init__(self, q0, settings):
        self.q0 = np.asarray(q0, float)
        self.settings = settings
        self._loads = {}
        self._t0 = {}
        self._tests = {}
        self._settled = set()

    def add_load(self, sample):
        """Register a commanded load sample (before its measurement arrives)."""
        self._loads[sample.index] = sample
        if sample.test_start or sample.test not in self._t0:
            self._t0[sample.test] = sample.t

    def _analyser(self, sample):
        if sample.test not in self._tests:
            if sample.kind == "static":
                self._tests[sample.test] = _Static(sample, self.q0)
            elif sample.kind == "decay":
                self._tests[sample.test] = _Decay(sample, self.q0)
            else:
                self._tests[sample.test] = _Harmonic(sample, self.q0, self.settings)
        return self._tests[sample.test]

    def add_measurement(self, measurement):
        """Consume a measurement; return a test name the first time its mean has settled."""
        sample = self._loads.pop(measurement.index)
        analyser = self._analyser(sample)
        tau = sample.t - self._t0[sample.test]
        analyser.add(sample, measurement.pose_vector(self.q0), tau)
        if isinstance(analyser, _Harmonic) and sample.test not in self._settled:
            if analyser.mean.settled:
                self._settled.add(sample.test)
                return sample.test
        return None

    def readings(self):
        """Readings of every test seen, by test name (in the order the tests ran)."""
        return {name: a.reading(name) for name, a in self._tests.items()}
