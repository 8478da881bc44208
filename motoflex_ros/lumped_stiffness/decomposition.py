"""Stiffness decomposition along the torsion and bending axes, eqs. (12a)-(12b).

Passigato et al. 2023, Sect. 4.2.3 (after their ref. [24]): the stiffness k about the static
deformation axis (angle beta, arm b) is split into k_t about the torsion axis (beta_t, b_t) and
k_b about the bending axis (beta_b, b_b) so that

    (12a)  b^2 / k = b_b^2 / k_b + b_t^2 / k_t
    (12b)  tan(beta) = (u sin(beta_b) + w sin(beta_t)) / (u cos(beta_b) + w cos(beta_t)),

with u = b_b / k_b, w = b_t / k_t [rad/(N m) * m]. (12b) is linear in (u, w):
u sin(beta - beta_b) = w sin(beta_t - beta); with (12a), b^2/k = b_b u + b_t w, it is a 2x2
linear system.

The solution is a pair of springs in series only if both are positive and finite. A negative
k_t (or k_b) means the static deflection cannot be built from the two axes with positive
springs, typically because the lateral load hardly excites that deformation (a straight tube
loaded sideways does not twist): :func:`split_problem` says why such a split is not
identifiable, and it must not be used as a stiffness.
"""
import math
from dataclasses import dataclass

import numpy as np

from motoflex_ros.errors import ModelError

__all__ = ["StiffnessSplit", "decompose_stiffness", "static_stiffness_from_split",
           "split_problem"]


@dataclass(frozen=True)
class StiffnessSplit:
    """k_t, k_b [N m/rad]: stiffness about the torsion and bending axes (eq. 12)."""

    k_t: float
    k_b: float


def decompose_stiffness(k, beta, b, beta_t, b_t, beta_b, b_b):
    """Eqs. (12a)-(12b): k_t and k_b from the static, torsion and bending axes.

    Parameters
    ----------
    k : float
        Stiffness about the static deformation axis [N m/rad] (eq. 8).
    beta, b : float
        Static axis angle to the line O-q0 [rad] and moment arm [m] (eqs. 6-7).
    beta_t, b_t : float
        Torsion axis angle [rad] and arm [m] (harmonic test at the first torsion frequency).
    beta_b, b_b : float
        Bending axis angle [rad] and arm [m] (harmonic test at the first bending frequency).

    Returns
    -------
    StiffnessSplit
        k_t, k_b [N m/rad].

    Examples
    --------
    Torsion and bending axes at 45 and 135 deg to O-q0, both with the arm 1 m, and the static
    axis across O-q0 (90 deg, arm 1 m) with k = 5000 N m/rad: the static axis bisects the two,
    so by symmetry k_t = k_b, and (12a) 1/k = 1/k_t + 1/k_b gives 10000 N m/rad each:

    >>> split = decompose_stiffness(5000.0, np.pi / 2, 1.0, np.pi / 4, 1.0, 3 * np.pi / 4, 1.0)
    >>> round(split.k_t, 6), round(split.k_b, 6)
    (10000.0, 10000.0)

    """
    a = np.array([[b_b, b_t], [np.sin(beta - beta_b), -np.sin(beta_t - beta)]])
    rhs = np.array([b**2 / k, 0.0])
    if abs(np.linalg.det(a)) < 1e-12 * max(abs(b_b), abs(b_t), 1e-300):
        raise ModelError("eq. (12) is singular: the torsion and bending axes coincide")
    u, w = np.linalg.solve(a, rhs)
    return StiffnessSplit(k_t=float(b_t / w), k_b=float(b_b / u))


def split_problem(k_t, k_b):
    """Why an eq. (12) split k_t, k_b [N m/rad] is not identifiable, or None if it is.

    Both must be positive and finite to be two springs in series about the torsion and bending
    axes; otherwise the returned sentence names the offending value(s) and the likely cause.
    """
    bad = [f"{name} = {value:.4g} N m/rad" for name, value in (("k_t", k_t), ("k_b", k_b))
           if not (math.isfinite(value) and value > 0)]
    if not bad:
        return None
    return (f"eq. (12) gives {' and '.join(bad)}, not a positive finite stiffness: the static "
            f"deflection is not a positive combination of rotations about the torsion and "
            f"bending axes (the lateral load does not excite that deformation)")


def static_stiffness_from_split(k_t, k_b, beta_t, b_t, beta_b, b_b, b):
    """Eqs. (12a)-(12b) forwards: static axis angle beta [rad] and k [N m/rad] of two springs.

    The small rotations about the torsion and bending axes add as vectors (u along beta_b,
    w along beta_t), which gives beta by (12b); k about that axis with arm b [m] follows from
    (12a): k = b^2 / (b_b^2/k_b + b_t^2/k_t).

    Parameters
    ----------
    k_t, k_b : float
        Stiffness about the torsion and bending axes [N m/rad].
    beta_t, b_t : float
        Torsion axis angle to O-q0 [rad] and arm [m].
    beta_b, b_b : float
        Bending axis angle [rad] and arm [m].
    b : float
        Arm of the static axis [m] (eq. 7).

    Returns
    -------
    (float, float)
        beta [rad] in [0, pi) and k [N m/rad] of the static axis.

    Examples
    --------
    Two equal 1e4 N m/rad springs about axes at 45 and 135 deg with equal arms turn the end
    about the bisector (90 deg), with half the stiffness for the same arm:

    >>> beta, k = static_stiffness_from_split(1e4, 1e4, np.pi / 4, 1.0, 3 * np.pi / 4, 1.0, 1.0)
    >>> round(beta / np.pi, 12), round(k, 6)
    (0.5, 5000.0)

    """
    u, w = b_b / k_b, b_t / k_t
    beta = float(np.mod(np.arctan2(u * np.sin(beta_b) + w * np.sin(beta_t),
                                   u * np.cos(beta_b) + w * np.cos(beta_t)), np.pi))
    return beta, float(b**2 / (b_b * u + b_t * w))
