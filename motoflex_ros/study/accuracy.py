"""Accuracy of a lumped model against the flexible one over speed, eq. (18).

Passigato et al. 2023, Sect. 5.2: e_RMS% of the frequency or the real part of weave or wobble
between 40 and 210 km/h. The mean of the flexible curve is taken in absolute value: real parts
of stable modes are negative and the paper's errors (Fig. 8) are positive percentages.
"""
import numpy as np

from motoflex_ros.errors import ModelError
from motoflex_ros.vehicle.mode_names import STUDIED_MODES

__all__ = ["QUANTITIES", "rms_error_percent", "weave_wobble_errors"]

QUANTITIES = ("weave_f", "weave_re", "wobble_f", "wobble_re")
"""The quantities whose e_RMS% the studies report (Fig. 8): frequency [Hz] and real part [1/s]
of weave and of wobble."""


def rms_error_percent(lumped, flexible, axis=-1):
    """Eq. (18): e_RMS% = sqrt(mean((x_lu - x_fl)^2)) / |mean(x_fl)| * 100 [%].

    Parameters
    ----------
    lumped, flexible : array (..., speeds)
        The same quantity (frequency [Hz] or real part [1/s]) of the lumped and the flexible
        model on the same N speeds; leading axes are batches (runs, modes, ...).
    axis : int
        The speed axis.

    Returns
    -------
    array (...)
        e_RMS% per batch entry; inf where the flexible mean is zero.

    Examples
    --------
    A lumped curve 0.1 Hz above a flexible one whose mean is 2 Hz is off by 5 %; one that is
    0.1 Hz off with alternating sign is off by the same:

    >>> flexible = [1.0, 2.0, 3.0]
    >>> round(float(rms_error_percent([1.1, 2.1, 3.1], flexible)), 9)
    5.0
    >>> round(float(rms_error_percent([0.9, 2.1, 2.9], flexible)), 9)
    5.0

    """
    lumped = np.asarray(lumped, dtype=float)
    flexible = np.asarray(flexible, dtype=float)
    if lumped.shape != flexible.shape:
        raise ModelError(f"lumped curve {lumped.shape} and flexible curve {flexible.shape} "
                         "must be on the same speeds")
    rms = np.sqrt(np.mean((lumped - flexible) ** 2, axis=axis))
    mean = np.abs(np.mean(flexible, axis=axis))
    with np.errstate(divide="ignore"):
        return np.where(mean > 0, 100.0 * rms / np.where(mean > 0, mean, 1.0), np.inf)


def weave_wobble_errors(lumped, flexible):
    """e_RMS% (eq. 18) of weave and wobble frequency [Hz] and real part [1/s], batched.

    Parameters
    ----------
    lumped : mapping
        {"weave", "wobble"}: eigenvalues [1/s], array (..., speeds).
    flexible : mapping
        {"weave", "wobble"}: eigenvalues [1/s] on the same speeds, array (speeds,) or the
        same shape as ``lumped``'s.

    Returns
    -------
    dict
        {quantity of QUANTITIES: e_RMS% [%], array (...)}.

    Examples
    --------
    A lumped wobble 0.1 Hz above a flexible one at 8 Hz, with the same real part -2 1/s, and a
    lumped weave identical to the flexible one:

    >>> flexible = {"weave": np.array([-1 + 2j, -1 + 2j]) * 2 * np.pi,
    ...             "wobble": np.array([-2 + 16j * np.pi, -2 + 16j * np.pi])}
    >>> lumped = {"weave": flexible["weave"], "wobble": flexible["wobble"] + 0.2j * np.pi}
    >>> {q: round(float(e), 9) for q, e in weave_wobble_errors(lumped, flexible).items()}
    {'weave_f': 0.0, 'weave_re': 0.0, 'wobble_f': 1.25, 'wobble_re': 0.0}

    """
    out = {}
    for mode in STUDIED_MODES:
        lu = np.asarray(lumped[mode])
        fl = np.broadcast_to(np.asarray(flexible[mode]), lu.shape)
        out[f"{mode}_f"] = rms_error_percent(lu.imag / (2 * np.pi), fl.imag / (2 * np.pi))
        out[f"{mode}_re"] = rms_error_percent(lu.real, fl.real)
    return out
