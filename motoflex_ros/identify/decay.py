"""Natural frequency and damping ratio from a free decay by the matrix-pencil method.

After release from a static preload the loaded end moves as a sum of damped exponentials
y(t_k) = sum_i r_i z_i^k, z_i = exp(lambda_i dt). The multi-channel matrix pencil (Hua & Sarkar,
IEEE Trans. ASSP 38 (1990) 814-824) stacks the Hankel matrices of all pose channels, keeps the
dominant right singular subspace V (model order from the singular values) and takes the
eigenvalues of pinv(V_1) V_2 (V without its last / first row) as the z_i. Then lambda_i =
ln(z_i) / dt and, by eq. (9), omega_n = |lambda|, zeta = -Re(lambda) / |lambda|. With exact data
the poles are exact; the model's modes are then picked by nearest omega_n.
"""
from dataclasses import dataclass

import numpy as np

from motoflex_ros.identify.stiffness import damping_ratio, natural_frequency

__all__ = ["DecayPole", "matrix_pencil_poles", "match_pole", "MAX_PENCIL", "ACTIVE_CHANNEL"]

ACTIVE_CHANNEL = 0.05  # channels swinging less than this fraction of the largest are left out
MAX_PENCIL = 150  # pencil parameter cap: above 2 x (number of modes), keeps the SVD small


@dataclass(frozen=True)
class DecayPole:
    """A pole from a free decay: eigenvalue [1/s], omega_n [rad/s], zeta [-]."""

    eigenvalue: complex
    omega_n: float
    zeta: float


def _hankel_stack(signals, pencil):
    """Stacked Hankel matrices of all channels, each (n - pencil) x (pencil + 1)."""
    n = signals.shape[0]
    rows = np.arange(n - pencil)[:, None] + np.arange(pencil + 1)[None, :]
    return np.vstack([signals[rows, ch] for ch in range(signals.shape[1])])


def _model_order(singular_values, relative_floor=1e-9, noise_factor=3.0):
    """Number of singular values above the noise floor.

    With white noise most singular values of the Hankel matrix lie on a plateau at the noise
    level; its median estimates it, and the poles kept are those more than ``noise_factor``
    times above it (and above ``relative_floor`` times the largest, for exact data).
    """
    floor = max(relative_floor * singular_values[0],
                noise_factor * float(np.median(singular_values)))
    return int(np.sum(singular_values > floor))


def matrix_pencil_poles(signals, dt, max_order=None):
    """Poles (Im > 0, ascending omega_n) of a multi-channel free decay.

    signals (n, channels) sampled at period dt [s], channels in comparable units (e.g. rotations
    times a length); channels that hardly move (the in-plane ones after a lateral release) carry
    only noise and are left out. Returns a list of :class:`DecayPole`.
    """
    signals = np.asarray(signals, float)
    swing = np.ptp(signals, axis=0)
    signals = signals[:, swing >= ACTIVE_CHANNEL * swing.max()]  # drop channels of noise only
    signals = signals / max(float(np.abs(signals).max()), 1e-300)
    pencil = min(signals.shape[0] // 3, MAX_PENCIL)
    _, sv, vt = np.linalg.svd(_hankel_stack(signals, pencil), full_matrices=False)
    order = _model_order(sv)
    if max_order is not None:
        order = min(order, max_order)
    v = vt[:order].T
    z = np.linalg.eigvals(np.linalg.pinv(v[:-1]) @ v[1:])
    lam = np.log(z.astype(complex)) / dt
    lam = lam[lam.imag > 0]
    poles = [DecayPole(complex(x), natural_frequency(x), damping_ratio(x)) for x in lam]
    return sorted(poles, key=lambda p: p.omega_n)


def match_pole(poles, omega_n, tolerance=0.05):
    """The pole nearest to omega_n [rad/s] within a relative tolerance, else None."""
    if not poles:
        return None
    best = min(poles, key=lambda p: abs(p.omega_n - omega_n))
    return best if abs(best.omega_n - omega_n) <= tolerance * omega_n else None
