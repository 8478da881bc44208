"""Marker-based displacement sensor of the loaded end, and the rigid fit that recovers its pose.

Markers are rigidly attached to the loaded end at offsets ``o_m`` [m] (component frame, unloaded).
A loaded end at position q [m] with orientation R puts marker m at ``q + R o_m``. The sensor
adds white Gaussian noise (standard deviation ``noise_m`` [m] per coordinate), rounds to its
``resolution_m`` [m] and delivers each measurement ``latency_s`` [s] after it was captured. The
pose is recovered by a least-squares rigid fit (Kabsch/SVD) of the measured markers to their
reference positions; :func:`fit_pose` takes any measured marker positions, simulated or real.

Noise comes from one seeded ``numpy.random.Generator`` drawn in a fixed order (one
``standard_normal((n_markers, 3))`` per captured sample), so a run is reproducible sample by
sample wherever the sensor object lives (offline loop or ROS node).
"""
from collections import deque
from dataclasses import dataclass

import numpy as np

from motoflex_ros.spatial import rotation_vector

__all__ = ["SensorSettings", "Measurement", "MarkerSensor", "fit_pose", "marker_positions",
           "DEFAULT_MARKERS", "MAX_NOISE_M", "MAX_SEED"]

# four non-coplanar markers on a plate of 0.15 m radius around the loaded end [m]
DEFAULT_MARKERS = ((0.15, 0.0, 0.0), (-0.075, 0.13, 0.0), (-0.075, -0.13, 0.0),
                   (0.0, 0.0, 0.15))

MAX_NOISE_M = 1e-3
"""Largest sensor noise [m] (standard deviation per coordinate) a protocol or an override may
give. The largest loaded-end displacement of the shipped protocols is 1.29 mm (the frame's
modal preload; its markers move by up to 1.9 mm, the front assembly's by 2.1 mm); static
deflections are 0.19-0.43 mm and harmonic amplitudes 0.08-0.68 mm. A noise above 1 mm exceeds
every static and harmonic deformation and is of the order of the largest one: the sensor would
see only noise. (Already at 1 mm the harmonic models are mostly noise: the bound refuses what
is meaningless, it does not promise accuracy below it.)"""
MAX_SEED = 2**31 - 1
"""Largest seed of the sensor noise (numpy takes any integer >= 0; ROS parameters are int32)."""


@dataclass(frozen=True)
class SensorSettings:
    """Sensor model: noise_m [m] (std per coordinate), resolution_m [m] (0: none), the maximum
    frame rate max_rate_hz [Hz], latency_s [s] and the marker offsets (n, 3) [m] from q0.
    """

    noise_m: float = 5e-6
    resolution_m: float = 1e-7
    max_rate_hz: float = 5000.0
    latency_s: float = 0.001
    markers: tuple = DEFAULT_MARKERS

    @property
    def nyquist_hz(self):
        """Nyquist frequency of the sensor at its maximum rate [Hz]."""
        return 0.5 * self.max_rate_hz


@dataclass(frozen=True)
class Measurement:
    """One sensor frame: sample index, capture stamp [s], measured markers (n, 3) [m] and the
    fitted pose of the loaded end: position [m] and rotation matrix (component frame).
    """

    index: int
    stamp: float
    markers: np.ndarray
    position: np.ndarray
    rotation: np.ndarray

    def pose_vector(self, q0):
        """(q - q0, rotation vector) as one 6-vector [m, rad]."""
        out = np.empty(6)
        out[:3] = self.position - q0
        out[3:] = rotation_vector(self.rotation)
        return out


def _det3(m):
    (a, b, c), (d, e, f), (g, h, i) = m.tolist()
    return a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g)


def marker_positions(position, rotation, q0, markers):
    """Marker positions (n, 3) [m] of a loaded end at (position, rotation); offsets from q0."""
    return np.asarray(position, float) + np.asarray(markers, float) @ np.asarray(rotation).T


def fit_pose(measured, reference, q0):
    """Least-squares rigid fit (Kabsch) of measured markers to their reference positions.

    Parameters
    ----------
    measured : (n, 3) array
        Measured marker positions [m], n >= 3 not collinear.
    reference : (n, 3) array
        The same markers with the component unloaded [m].
    q0 : (3,) array
        Loaded end, unloaded [m].

    Returns
    -------
    position, rotation
        q [m] and R minimising sum |R (p_ref - q0) + q - p_meas|^2.

    """
    measured = np.asarray(measured, float)
    reference = np.asarray(reference, float)
    scale = 1.0 / len(measured)
    c_meas, c_ref = measured.sum(axis=0) * scale, reference.sum(axis=0) * scale
    h = (reference - c_ref).T @ (measured - c_meas)
    u, _, vt = np.linalg.svd(h)
    if _det3(u) * _det3(vt) < 0.0:  # reflection: flip the weakest direction
        vt = vt * np.array([[1.0], [1.0], [-1.0]])
    rotation = vt.T @ u.T
    position = c_meas - rotation @ (c_ref - q0)
    return position, rotation


class MarkerSensor:
    """Stage object: turns true poses of the loaded end into delayed, noisy measurements.

    ``capture(index, t, position, rotation)`` (or ``capture_markers(index, t, true_markers)``,
    which gives bit-identical results from the true marker positions a simulator publishes)
    measures one sample and returns the measurements whose latency has elapsed by time ``t``
    (a list, usually of one); ``flush()`` returns the rest at the end of a campaign.
    """

    def __init__(self, settings, q0, seed=0):
        self.settings = settings
        self.q0 = np.asarray(q0, float)
        self.offsets = np.asarray(settings.markers, float)
        self.reference = self.q0 + self.offsets
        self.rng = np.random.default_rng(seed)
        self._queue = deque()

    def add_noise(self, true_markers):
        """Measured markers from true ones: noise, then rounding (consumes the generator) [m]."""
        true_markers = np.asarray(true_markers, float)
        noisy = true_markers + self.settings.noise_m * self.rng.standard_normal(
            true_markers.shape)
        res = self.settings.resolution_m
        return np.round(noisy / res) * res if res > 0 else noisy

    def measurement(self, index, stamp, markers):
        """A :class:`Measurement` from measured markers (simulated or real) [m]."""
        position, rotation = fit_pose(markers, self.reference, self.q0)
        return Measurement(index, float(stamp), markers, position, rotation)

    def capture_markers(self, index, t, true_markers):
        """Capture sample ``index`` at time t [s] from the true marker positions (n, 3) [m];
        return the measurements now delivered (those whose latency has elapsed)."""
        self._queue.append(self.measurement(index, t, self.add_noise(true_markers)))
        ready = []
        while self._queue and self._queue[0].stamp + self.settings.latency_s <= t + 1e-12:
            ready.append(self._queue.popleft())
        return ready

    def capture(self, index, t, position, rotation):
        """Capture sample ``index`` at time t [s] of a loaded end at (position [m], rotation);
        the same as :meth:`capture_markers` of its true markers."""
        return self.capture_markers(index, t, marker_positions(position, rotation, self.q0,
                                                               self.offsets))

    def flush(self):
        """All measurements still waiting for their latency to elapse."""
        ready = list(self._queue)
        self._queue.clear()
        return ready
