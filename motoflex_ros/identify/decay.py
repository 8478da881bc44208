"""Natural frequency and damping ratio from a free decay by the matrix-pencil method.

After release from a static preload the loaded end moves as a sum of damped exponentials
y(t_k) = sum_i r_i z_i^k, z_i = exp(lambda_i dt). The multi-channel matrix pencil
(:mod:`motoflex_ros.identify.matrix_pencil`, Hua & Sarkar 1990) on all pose channels gives the
lambda_i; by eq. (9), omega_n = |lambda|, zeta = -Re(lambda) / |lambda|. With exact data the
poles are exact; the model's modes are then picked by nearest omega_n.

Uncertainty: a residual bootstrap over the sensor noise (Efron & Tibshirani 1993, ch. 9). The
poles' residues are fitted to the record by least squares; the residual (record minus fit) is
the noise the sensor added (plus the modes too weak to stand above it). Replicas are the fit
plus the residual's rows drawn with replacement (rows, so that the correlation between the pose
channels of one frame is kept); the pencil is run again on each. The spread of a pole's
omega_n and zeta over the replicas in which it is found again gives its 95 % interval
(value +/- 1.96 sd, as the other identified values). A pole found again in fewer than half of
the replicas does not stand above the noise: its interval is undefined (NaN).
"""
import math
from dataclasses import dataclass

import numpy as np

from motoflex_ros.identify.matrix_pencil import matrix_pencil_poles
from motoflex_ros.identify.stiffness import damping_ratio, natural_frequency
from motoflex_ros.identify.uncertainty import interval

__all__ = ["DecayPole", "decay_poles", "match_pole", "MAX_PENCIL", "ACTIVE_CHANNEL",
           "BOOTSTRAP_REPLICAS"]

ACTIVE_CHANNEL = 0.05  # channels swinging less than this fraction of the largest are left out
MAX_PENCIL = 150  # pencil parameter cap: above 2 x (number of modes), keeps the SVD small
NOISE_FACTOR = 3.0  # poles kept: singular values above 3 x the noise plateau (their median)
BOOTSTRAP_REPLICAS = 30  # residual-bootstrap replicas: sd to ~13 %, 5-15 ms each (fixed seed)
BOOTSTRAP_SEED = 0  # the intervals are reproducible: same record, same interval
MATCH_TOLERANCE = 0.05  # a pole is 'the same' within this relative distance in omega_n
MIN_FOUND_SHARE = 0.5  # below this share of replicas finding a pole, its interval is undefined

_UNDEFINED = (math.nan, math.nan)


@dataclass(frozen=True)
class DecayPole:
    """A pole from a free decay: eigenvalue [1/s], omega_n [rad/s], zeta [-], their 95 %
    intervals omega_n_ci [rad/s] and zeta_ci [-] (NaN: undefined) and the number of bootstrap
    replicas that found the pole again (n_bootstrap of them ran)."""

    eigenvalue: complex
    omega_n: float
    zeta: float
    omega_n_ci: tuple = _UNDEFINED
    zeta_ci: tuple = _UNDEFINED
    n_found: int = 0
    n_bootstrap: int = 0


def _active(signals):
    """Channels that swing (noise-only channels dropped), scaled together to unit peak."""
    swing = np.ptp(signals, axis=0)
    signals = signals[:, swing >= ACTIVE_CHANNEL * swing.max()]
    return signals / max(float(np.abs(signals).max()), 1e-300)


def _poles(signals, dt):
    pencil = min(signals.shape[0] // 3, MAX_PENCIL)
    return matrix_pencil_poles(signals, dt, pencil, noise_factor=NOISE_FACTOR)


def _fit(signals, lam, dt):
    """Least-squares sum of the damped exponentials exp(lam t_k) fitted to each channel."""
    basis = np.exp(np.outer(np.arange(signals.shape[0]) * dt, lam))
    residues = np.linalg.lstsq(basis, signals.astype(complex), rcond=None)[0]
    return (basis @ residues).real


def _bootstrap(signals, lam, dt, replicas, seed):
    """Upper-half-plane poles of ``replicas`` residual-bootstrap replicas of ``signals``."""
    fitted = _fit(signals, lam, dt)
    residual = signals - fitted
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(replicas):
        rows = rng.integers(0, signals.shape[0], signals.shape[0])
        found = _poles(fitted + residual[rows], dt)
        out.append(found[found.imag > 0])
    return out


def _with_interval(value, replicas):
    """DecayPole of eigenvalue ``value`` with intervals from the replicas that find it."""
    omega, zeta = natural_frequency(value), damping_ratio(value)
    pole = DecayPole(complex(value), omega, zeta, n_bootstrap=len(replicas))
    hits = []
    for lam in replicas:
        if len(lam):
            near = lam[np.argmin(np.abs(np.abs(lam) - omega))]
            if abs(abs(near) - omega) <= MATCH_TOLERANCE * omega:
                hits.append((natural_frequency(near), damping_ratio(near)))
    if len(hits) < max(2, MIN_FOUND_SHARE * len(replicas)):
        return DecayPole(pole.eigenvalue, omega, zeta, n_found=len(hits),
                         n_bootstrap=len(replicas))
    var = np.var(np.array(hits), axis=0, ddof=1)
    return DecayPole(pole.eigenvalue, omega, zeta, tuple(interval(omega, var[0])),
                     tuple(interval(zeta, var[1])), len(hits), len(replicas))


def decay_poles(signals, dt, replicas=BOOTSTRAP_REPLICAS, seed=BOOTSTRAP_SEED):
    """Poles (Im > 0, ascending omega_n) of a multi-channel free decay, with 95 % intervals.

    Parameters
    ----------
    signals : array (n, channels)
        Loaded-end motion sampled at period ``dt`` [s], channels in comparable units (e.g.
        rotations times a length). Channels that hardly move (the in-plane ones after a lateral
        release) carry only noise and are left out; the rest are scaled together to unit peak.
    dt : float
        Sample period [s].
    replicas : int
        Residual-bootstrap replicas for the intervals (module doc; 0: no intervals).
    seed : int
        Seed of the bootstrap's row draws [-].

    Returns
    -------
    list of DecayPole
        omega_n = |lambda| [rad/s], zeta = -Re(lambda) / |lambda| [-] (eq. 9) with their 95 %
        intervals; pencil parameter min(n / 3, MAX_PENCIL), model order above the noise floor
        (3 x the median singular value).

    Examples
    --------
    An exact free decay at omega_n = 2 pi 10 rad/s with zeta = 0.02 (two channels, cosine and
    sine of the damped frequency omega_n sqrt(1 - zeta^2)) gives that one pole back:

    >>> omega, zeta, dt = 20 * np.pi, 0.02, 1e-3
    >>> t = np.arange(600) * dt
    >>> phase = omega * np.sqrt(1 - zeta**2) * t
    >>> record = np.exp(-zeta * omega * t)[:, None] * np.column_stack([np.cos(phase),
    ...                                                                 np.sin(phase)])
    >>> [(round(p.omega_n / (2 * np.pi), 9), round(p.zeta, 9))
    ...  for p in decay_poles(record, dt, replicas=0)]
    [(10.0, 0.02)]

    """
    signals = _active(np.asarray(signals, float))
    lam = _poles(signals, dt)
    boot = _bootstrap(signals, lam, dt, replicas, seed) if replicas else []
    poles = [_with_interval(x, boot) for x in lam[lam.imag > 0]]
    return sorted(poles, key=lambda p: p.omega_n)


def match_pole(poles, omega_n, tolerance=MATCH_TOLERANCE):
    """The pole nearest to omega_n [rad/s] within a relative tolerance, else None."""
    if not poles:
        return None
    best = min(poles, key=lambda p: abs(p.omega_n - omega_n))
    return best if abs(best.omega_n - omega_n) <= tolerance * omega_n else None
