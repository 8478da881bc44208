"""Natural frequency and damping ratio from a free decay by the matrix-pencil method.

After release from a static preload the loaded end moves as a sum of damped exponentials
y(t_k) = sum_i r_i z_i^k, z_i = exp(lambda_i dt). The multi-channel matrix pencil
(:mod:`motoflex_ros.identify.matrix_pencil`, Hua & Sarkar 1990) on all pose channels gives the
lambda_i; by eq. (9), omega_n = |lambda|, zeta = -Re(lambda) / |lambda|. With exact data the
poles are exact; the model's modes are then picked by nearest omega_n.
"""
from dataclasses import dataclass

import numpy as np

from motoflex_ros.identify.matrix_pencil import matrix_pencil_poles
from motoflex_ros.identify.stiffness import damping_ratio, natural_frequency

__all__ = ["DecayPole", "decay_poles", "match_pole", "MAX_PENCIL", "ACTIVE_CHANNEL"]

ACTIVE_CHANNEL = 0.05  # channels swinging less than this fraction of the largest are left out
MAX_PENCIL = 150  # pencil parameter cap: above 2 x (number of modes), keeps the SVD small
NOISE_FACTOR = 3.0  # poles kept: singular values above 3 x the noise plateau (their median)


@dataclass(frozen=True)
class DecayPole:
    """A pole from a free decay: eigenvalue [1/s], omega_n [rad/s], zeta [-]."""

    eigenvalue: complex
    omega_n: float
    zeta: float


def decay_poles(signals, dt):
    """Poles (Im > 0, ascending omega_n) of a multi-channel free decay.

    Parameters
    ----------
    signals : array (n, channels)
        Loaded-end motion sampled at period ``dt`` [s], channels in comparable units (e.g.
        rotations times a length). Channels that hardly move (the in-plane ones after a lateral
        release) carry only noise and are left out; the rest are scaled together to unit peak.
    dt : float
        Sample period [s].

    Returns
    -------
    list of DecayPole
        omega_n = |lambda| [rad/s], zeta = -Re(lambda) / |lambda| [-] (eq. 9); pencil parameter
        min(n / 3, MAX_PENCIL), model order above the noise floor (3 x the median singular
        value).

    """
    signals = np.asarray(signals, float)
    swing = np.ptp(signals, axis=0)
    signals = signals[:, swing >= ACTIVE_CHANNEL * swing.max()]  # drop channels of noise only
    signals = signals / max(float(np.abs(signals).max()), 1e-300)
    pencil = min(signals.shape[0] // 3, MAX_PENCIL)
    lam = matrix_pencil_poles(signals, dt, pencil, noise_factor=NOISE_FACTOR)
    lam = lam[lam.imag > 0]
    poles = [DecayPole(complex(x), natural_frequency(x), damping_ratio(x)) for x in lam]
    return sorted(poles, key=lambda p: p.omega_n)


def match_pole(poles, omega_n, tolerance=0.05):
    """The pole nearest to omega_n [rad/s] within a relative tolerance, else None."""
    if not poles:
        return None
    best = min(poles, key=lambda p: abs(p.omega_n - omega_n))
    return best if abs(best.omega_n - omega_n) <= tolerance * omega_n else None
