"""Stability index of a tracked mode over a speed range, eqs. (13)-(15).

Passigato et al. 2023, Sect. 4.3, Fig. 4. The input is the real part of one tracked mode
(weave or wobble) on a speed grid, for many runs at once: an array ``runs x speeds`` [1/s]
with the speeds [m/s] shared by all runs. Between grid points the real part is taken as
linear in speed (the same interpolation that finds the crossing speeds).

Interpretation of eq. (15), s = |min(0, s1)| + s2, used here for every run:

* s1 (eq. 13) is the largest real part over the range [1/s].
* s2 (eq. 14) is the length of the speed set where the mode is stable (Re <= 0) divided by
  the length of the range, computed the same way for every curve: crossings are the zeros
  of the linear interpolant, any number of them.
* Never crossed (s1 < 0): the whole range is stable, so s2 = 1 and s = 1 + |s1| > 1, the
  paper's "minimum distance between the curve and the stability boundary" plus one.
* Crossed (s1 > 0): min(0, s1) = 0 and s = s2 in [0, 1); s = 0 when unstable everywhere.
* Touching without crossing (s1 = 0): s2 = 1 and s = 1, the paper's boundary case.

So s is continuous through the boundary case and grows with damping; its first part has
units of 1/s and its second is dimensionless, exactly as in the paper. A real part of
exactly zero counts as stable (the paper: "at the stability threshold ... maximum stability").
"""
from dataclasses import dataclass

import numpy as np

from motoflex_ros.errors import ModelError
from motoflex_ros.units import kmh_to_ms
from motoflex_ros.vehicle.mode_names import STUDIED_MODES

__all__ = ["SPEED_RANGES_KMH", "RANGE_NAMES", "INDEX_NAMES", "StabilityIndex", "speed_range",
           "max_real_part", "stable_fraction", "combined_index", "stability_index",
           "crossing_speeds"]

# the paper's low and high speed ranges [km/h] (Sect. 4.3)
SPEED_RANGES_KMH = {"low": (40.0, 100.0), "high": (100.0, 210.0)}
RANGE_NAMES = tuple(SPEED_RANGES_KMH)   # ("low", "high")
INDEX_NAMES = tuple(f"{mode}_{r}" for mode in STUDIED_MODES for r in RANGE_NAMES)
"""The four stability indices of the sensitivity and design studies, "<mode>_<range>":
weave_low, weave_high, wobble_low, wobble_high."""


def speed_range(name):
    """The paper's speed range ``"low"`` (40-100 km/h) or ``"high"`` (100-210 km/h) in [m/s]."""
    if name not in SPEED_RANGES_KMH:
        raise ModelError(f"speed range '{name}' does not exist; allowed: "
                         f"{', '.join(SPEED_RANGES_KMH)}")
    low, high = SPEED_RANGES_KMH[name]
    return float(kmh_to_ms(low)), float(kmh_to_ms(high))


@dataclass(frozen=True)
class StabilityIndex:
    """Stability indices of one mode over one speed range, one value per run.

    s1 [1/s] (eq. 13), s2 [-] (eq. 14), s (eq. 15; |s1| part in 1/s, s2 part dimensionless).
    """

    s1: np.ndarray
    s2: np.ndarray
    s: np.ndarray


def _segments_in_range(speeds, real_parts, v_range):
    """Linear pieces of Re(lambda)(v) clipped to v_range: start/end values and lengths."""
    speeds = np.asarray(speeds, dtype=float)
    re = np.atleast_2d(np.asarray(real_parts, dtype=float))
    v_min, v_max = (float(v) for v in v_range)
    if speeds.ndim != 1 or speeds.size < 2 or np.any(np.diff(speeds) <= 0):
        raise ModelError("speeds must be a strictly increasing 1-D grid of at least 2 values")
    if re.shape[-1] != speeds.size:
        raise ModelError(f"real parts have {re.shape[-1]} speeds, the grid has {speeds.size}")
    if not speeds[0] <= v_min < v_max <= speeds[-1]:
        raise ModelError(f"speed range [{v_min:.4g}, {v_max:.4g}] m/s is not inside the grid "
                         f"[{speeds[0]:.4g}, {speeds[-1]:.4g}] m/s")
    lo = np.clip(speeds[:-1], v_min, v_max)
    hi = np.clip(speeds[1:], v_min, v_max)
    slope = np.diff(re, axis=-1) / np.diff(speeds)
    start = re[..., :-1] + slope * (lo - speeds[:-1])
    end = re[..., :-1] + slope * (hi - speeds[:-1])
    return start, end, hi - lo


def max_real_part(speeds, real_parts, v_range):
    """Eq. (13): s1 = max Re(lambda) over the speed range [1/s], per run.

    Parameters
    ----------
    speeds : array (speeds,)
        Strictly increasing speed grid [m/s] covering ``v_range``.
    real_parts : array (runs, speeds) or (speeds,)
        Real part of the tracked mode [1/s].
    v_range : (float, float)
        v_min, v_max [m/s].

    Returns
    -------
    array (runs,)
        s1 [1/s].

    Examples
    --------
    Re = -1, +1, -1 1/s at 0, 10 and 20 m/s: the peak is +1 at 10 m/s, and over 0-5 m/s the
    largest value is where the line reaches 0:

    >>> speeds, re = [0.0, 10.0, 20.0], [-1.0, 1.0, -1.0]
    >>> max_real_part(speeds, re, (0.0, 20.0)).tolist()
    [1.0]
    >>> max_real_part(speeds, re, (0.0, 5.0)).tolist()
    [0.0]

    """
    start, end, length = _segments_in_range(speeds, real_parts, v_range)
    inside = length > 0
    return np.maximum(start[..., inside], end[..., inside]).max(axis=-1)


def stable_fraction(speeds, real_parts, v_range):
    """Eq. (14): s2 = ||v_stable|| / (v_max - v_min) [-], per run.

    On each linear piece with end values a, b the stable part (Re <= 0) has the length
    L (max(-a, 0) + max(-b, 0)) / (|a| + |b|) (the crossing by linear interpolation), and L when
    a = b = 0. Any number of crossings is handled.

    Parameters
    ----------
    speeds : array (speeds,)
        Strictly increasing speed grid [m/s] covering ``v_range``.
    real_parts : array (runs, speeds) or (speeds,)
        Real part of the tracked mode [1/s].
    v_range : (float, float)
        v_min, v_max [m/s].

    Returns
    -------
    array (runs,)
        s2 [-] in [0, 1].

    Examples
    --------
    The curve of :func:`max_real_part` crosses zero at 5 and 15 m/s: stable on 0-5 and
    15-20 m/s, half the range:

    >>> stable_fraction([0.0, 10.0, 20.0], [-1.0, 1.0, -1.0], (0.0, 20.0)).tolist()
    [0.5]

    """
    start, end, length = _segments_in_range(speeds, real_parts, v_range)
    negative = np.maximum(-start, 0.0) + np.maximum(-end, 0.0)
    total = np.abs(start) + np.abs(end)
    share = np.divide(negative, total, out=np.ones_like(total), where=total > 0)
    return (share * length).sum(axis=-1) / (float(v_range[1]) - float(v_range[0]))


def combined_index(s1, s2):
    """Eq. (15): s = |min(0, s1)| + s2 (see the module notes for the two situations).

    Parameters
    ----------
    s1 : array or float
        Largest real part over the range [1/s] (eq. 13).
    s2 : array or float
        Stable share of the range [-] (eq. 14).

    Returns
    -------
    array or float
        s (the |s1| part in 1/s, the s2 part dimensionless).

    Examples
    --------
    Never crossed (s1 = -0.2 1/s, s2 = 1): s = 1.2; crossed (s1 = 0.3, s2 = 0.4): s = s2:

    >>> float(combined_index(-0.2, 1.0)), float(combined_index(0.3, 0.4))
    (1.2, 0.4)

    """
    return np.abs(np.minimum(0.0, s1)) + s2


def stability_index(speeds, real_parts, v_range):
    """Eqs. (13)-(15) for every run: a :class:`StabilityIndex` of arrays (runs,).

    Parameters
    ----------
    speeds : array (speeds,)
        Strictly increasing speed grid [m/s] covering ``v_range``.
    real_parts : array (runs, speeds) or (speeds,)
        Real part of the tracked mode [1/s].
    v_range : (float, float) or str
        v_min, v_max [m/s], or ``"low"`` (40-100 km/h) or ``"high"`` (100-210 km/h).

    Returns
    -------
    StabilityIndex
        s1 [1/s], s2 [-] and s per run.

    Examples
    --------
    A mode at least 1 1/s inside the stable half-plane over 10-30 m/s: s1 = -1, s2 = 1,
    s = 1 + |s1| = 2:

    >>> index = stability_index([10.0, 20.0, 30.0], [[-2.0, -1.0, -3.0]], (10.0, 30.0))
    >>> index.s1.tolist(), index.s2.tolist(), index.s.tolist()
    ([-1.0], [1.0], [2.0])

    """
    if isinstance(v_range, str):
        v_range = speed_range(v_range)
    s1 = max_real_part(speeds, real_parts, v_range)
    s2 = stable_fraction(speeds, real_parts, v_range)
    return StabilityIndex(s1=s1, s2=s2, s=combined_index(s1, s2))


def crossing_speeds(speeds, real_part):
    """Speeds [m/s] where one curve Re(lambda)(v) [1/s] crosses zero, by linear interpolation.

    A point exactly on zero counts once; a curve that only touches zero at a grid point with
    the same sign on both sides does not cross there.
    """
    speeds = np.asarray(speeds, dtype=float)
    re = np.asarray(real_part, dtype=float)
    sign = np.sign(re)
    nonzero = np.flatnonzero(sign != 0)
    before, after = nonzero[:-1], nonzero[1:]
    flip = sign[before] != sign[after]
    result = []
    for i, j in zip(before[flip], after[flip]):
        if j > i + 1:  # zero grid point(s) in between: the crossing is the first of them
            result.append(speeds[i + 1])
        else:
            result.append(speeds[i] - re[i] * (speeds[j] - speeds[i]) / (re[j] - re[i]))
    return np.asarray(result)
