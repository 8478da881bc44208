"""Linear propagation of measurement uncertainty to identified values.

An identified value y = g(x) computed from measured quantities x with covariance S gets the
covariance G S G^T, G the Jacobian of g by central differences. The covariance of x comes from
the scatter of the measurements themselves (the standard error of a mean over samples or
peaks), so the same code applies to real measurements with unknown noise. Intervals are
value +/- z sqrt(var), z the two-sided normal (or Student t) quantile of the level. With a
single sample there is no spread estimate: the covariance is NaN and so is the interval
(undefined, never zero width).
"""
import math

import numpy as np

__all__ = ["jacobian", "propagate", "mean_and_covariance", "interval", "LEVEL"]

LEVEL = 0.95


def jacobian(func, x, steps):
    """Central-difference Jacobian of func at x with per-component steps."""
    x = np.asarray(x, float)
    cols = []
    for i, h in enumerate(steps):
        dx = np.zeros_like(x)
        dx[i] = h
        cols.append((np.asarray(func(x + dx)) - np.asarray(func(x - dx))) / (2.0 * h))
    return np.column_stack(cols)


def propagate(func, x, cov, steps):
    """Value and covariance of func(x) given cov(x) (linear propagation)."""
    g = jacobian(func, x, steps)
    return np.asarray(func(np.asarray(x, float))), g @ np.asarray(cov) @ g.T


def mean_and_covariance(samples):
    """Mean of the rows of ``samples`` (n, m) and the covariance of that mean (S / n); the
    covariance is NaN for n < 2 (one sample says nothing about the scatter)."""
    samples = np.asarray(samples, float)
    n = samples.shape[0]
    if n < 2:
        return samples.mean(axis=0), np.full((samples.shape[1],) * 2, np.nan)
    return samples.mean(axis=0), np.cov(samples, rowvar=False).reshape(
        samples.shape[1], samples.shape[1]) / n


def interval(value, variance, dof=None, level=LEVEL):
    """Two-sided interval [lo, hi] of ``level``; Student t with ``dof`` degrees if given.

    [nan, nan] (undefined) when the variance is not finite or ``dof`` < 1: without a spread
    estimate there is no interval, and a zero-width one would claim an exact value.
    """
    variance = float(variance)
    if not math.isfinite(variance) or (dof is not None and dof < 1):
        return [math.nan, math.nan]
    # the quantile functions themselves (what scipy.stats' t.ppf and norm.ppf call, bitwise the
    # same): importing scipy.stats costs about 1 CPU-s per process, scipy.special a quarter
    from scipy.special import ndtri, stdtrit
    q = stdtrit(dof, 0.5 + level / 2) if dof is not None else ndtri(0.5 + level / 2)
    half = q * np.sqrt(max(variance, 0.0))
    return [float(value - half), float(value + half)]
