"""Poles of a multi-channel free response by the matrix-pencil method.

Hua & Sarkar, "Matrix pencil method for estimating parameters of exponentially damped/undamped
sinusoids in noise", IEEE Trans. ASSP 38(5) (1990) 814-824. A free response is a sum of damped
exponentials, y(t_k) = sum_i r_i z_i^k with z_i = exp(s_i dt). The Hankel matrices of all
channels, each (N - L) x (L + 1) for the pencil parameter L, are stacked into Y; with
Y = U S V^T truncated to its M significant singular values (S and V taken from the SVD of R,
Y = Q R, for a tall Y: the same values at half the cost), the poles are
z_i = eig(pinv(V_1) V_2), V_1 / V_2 the rows of V without its last / first one, and
s_i = ln(z_i) / dt.

Used by the bench (free decay of a clamped component, :mod:`motoflex_ros.identify.decay`) and
by the vehicle's virtual road test (steer-pulse response, :mod:`motoflex_ros.vehicle.steer_pulse`).
"""
import numpy as np

__all__ = ["matrix_pencil_poles", "model_order", "unit_peak"]


def _hankel_stack(signals, pencil):
    """Stacked Hankel matrices of all channels, each (n - pencil) x (pencil + 1)."""
    n = signals.shape[0]
    rows = np.arange(n - pencil)[:, None] + np.arange(pencil + 1)[None, :]
    return np.vstack([signals[rows, ch] for ch in range(signals.shape[1])])


def model_order(singular_values, rtol=1e-9, noise_factor=0.0):
    """Number M of significant singular values of the stacked Hankel matrix.

    Parameters
    ----------
    singular_values : array (descending)
        Singular values of the stacked Hankel matrix [signal units].
    rtol : float
        Values at or below ``rtol`` times the largest are rounding (exact data) [-].
    noise_factor : float
        With white noise most singular values lie on a plateau at the noise level; its median
        estimates it, and only values more than ``noise_factor`` times above it count [-]
        (0: no noise floor).

    Returns
    -------
    int
        The model order M.

    """
    floor = max(rtol * singular_values[0], noise_factor * float(np.median(singular_values)))
    return int(np.sum(singular_values > floor))


def unit_peak(signals):
    """Each channel of ``signals`` (n, m) divided by its largest |y| (an all-zero channel kept).

    Channels in different units (e.g. an angle [rad] and a rate [rad/s]) then weigh alike in
    the stacked Hankel matrix.
    """
    signals = np.atleast_2d(np.asarray(signals, float).T).T
    scale = np.array([np.max(np.abs(y)) or 1.0 for y in signals.T])
    return signals / scale


def matrix_pencil_poles(signals, dt, pencil=None, order=None, rtol=1e-9, noise_factor=0.0):
    """Continuous-time poles s_i [1/s] of a free response by the matrix pencil (module doc).

    Parameters
    ----------
    signals : array (n,) or (n, m)
        Free-response samples, one column per channel, weighted as given: put channels in
        comparable units first (e.g. :func:`unit_peak`).
    dt : float
        Sample period [s].
    pencil : int, optional
        Pencil parameter L (default n // 2; Hua & Sarkar recommend n/3 <= L <= n/2).
    order : int, optional
        Model order M (default :func:`model_order` with ``rtol`` and ``noise_factor``).
    rtol, noise_factor : float
        Passed to :func:`model_order` when ``order`` is not given [-].

    Returns
    -------
    ndarray of complex
        All M poles s_i = ln(z_i) / dt [1/s], complex-conjugate pairs included, unsorted.

    """
    signals = np.atleast_2d(np.asarray(signals, float).T).T
    if pencil is None:
        pencil = signals.shape[0] // 2
    hankel = _hankel_stack(signals, pencil)
    if hankel.shape[0] > hankel.shape[1]:  # same S, V from the triangular factor, 2x faster
        hankel = np.linalg.qr(hankel, mode="r")
    _, sv, vt = np.linalg.svd(hankel, full_matrices=False)
    if order is None:
        order = model_order(sv, rtol, noise_factor)
    v = vt[:order].T
    z = np.linalg.eigvals(np.linalg.pinv(v[:-1]) @ v[1:])
    return np.log(z.astype(complex)) / dt
