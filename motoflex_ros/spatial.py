"""Vector and rotation helpers shared by the structures, the bench and the vehicle engine.

``cross``, ``skew``, ``unit`` and ``rotation`` are complex-step safe (no abs, norm or branching
on values): they accept real or complex arrays so that the residual of the vehicle's equations
of motion can be differentiated by the complex-step method. ``rotation_from_vector`` and
``rotation_vector`` convert between rotation vectors and matrices for measured (real) poses,
accurately down to vanishing angles; ``quaternion_xyzw`` gives a matrix's quaternion.
"""
import math

import numpy as np

__all__ = ["cross", "skew", "unit", "rotation", "rotation_from_vector", "rotation_vector",
           "quaternion_xyzw"]

_IDENTITY = np.eye(3)


def cross(a, b):
    """Cross product a x b of two 3-vectors (complex-safe)."""
    return np.array([a[1] * b[2] - a[2] * b[1],
                     a[2] * b[0] - a[0] * b[2],
                     a[0] * b[1] - a[1] * b[0]])


def skew(a):
    """Cross-product matrix [a]x of a 3-vector, so that ``skew(a) @ b`` is a x b."""
    return np.array([[0.0 * a[0], -a[2], a[1]],
                     [a[2], 0.0 * a[0], -a[0]],
                     [-a[1], a[0], 0.0 * a[0]]])


def unit(a):
    """Unit vector a / sqrt(a . a) (analytic continuation of the normalisation, complex-safe)."""
    return a / np.sqrt(a @ a)


def rotation(axis, angle):
    """Rotation matrix about the unit vector ``axis`` by ``angle`` [rad] (Rodrigues).

    R = 1 + sin(angle) [a]x + (1 - cos(angle)) [a]x^2; complex-safe in axis and angle.
    """
    k = skew(axis)
    return np.eye(3) + np.sin(angle) * k + (1.0 - np.cos(angle)) * (k @ k)


def rotation_from_vector(theta):
    """Rotation matrix exp([theta]x) of a rotation vector theta [rad] (Rodrigues).

    R = 1 + sin|theta| / |theta| [theta]x + (1 - cos|theta|) / |theta|^2 [theta]x^2, with the
    limits 1 and 1/2 of the two factors below |theta| = 1e-8 rad (real theta only).
    """
    x, y, z = (float(v) for v in theta)
    angle = math.sqrt(x * x + y * y + z * z)
    cross_matrix = skew((x, y, z))
    if angle < 1e-8:
        first, second = 1.0, 0.5
    else:
        first, second = math.sin(angle) / angle, (1.0 - math.cos(angle)) / angle**2
    return _IDENTITY + first * cross_matrix + second * (cross_matrix @ cross_matrix)


def rotation_vector(rotation):
    """Rotation vector [rad] of a rotation matrix (inverse of :func:`rotation_from_vector`).

    Uses the skew part for the axis and atan2 for the angle, accurate for small rotations.
    """
    r = np.asarray(rotation, float)
    vx, vy, vz = 0.5 * (r[2, 1] - r[1, 2]), 0.5 * (r[0, 2] - r[2, 0]), 0.5 * (r[1, 0] - r[0, 1])
    sin_angle = math.sqrt(vx * vx + vy * vy + vz * vz)
    if sin_angle < 1e-300:
        return np.zeros(3)
    angle = math.atan2(sin_angle, 0.5 * (r[0, 0] + r[1, 1] + r[2, 2] - 1.0))
    return np.array([vx, vy, vz]) * (angle / sin_angle)


def quaternion_xyzw(rotation):
    """Unit quaternion (x, y, z, w) of a rotation matrix, the order ROS messages and scipy use.

    Parameters
    ----------
    rotation : array_like, shape (3, 3)
        Proper rotation matrix [-].

    Returns
    -------
    tuple of float
        (x, y, z, w) [-]: the vector part, then the scalar part.

    Notes
    -----
    Shepperd's method (S. W. Shepperd, "Quaternion from rotation matrix", J. Guidance and
    Control 1(3), 1978): the w >= 0 branch when the trace is positive (every small rotation
    of the bench), else the branch of the largest diagonal element, which keeps the divisor
    away from zero. scipy's ``Rotation.from_matrix(r).as_quat()`` gives
    the same to 1e-15 (test/test_nodes_config.py) at about 50x the cost per matrix
    (:mod:`motoflex_ros.nodes.conversions` gives the numbers).

    Examples
    --------
    A quarter turn about z:

    >>> x, y, z, w = quaternion_xyzw([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
    >>> print(f"{x:.4f} {y:.4f} {z:.4f} {w:.4f}")
    0.0000 0.0000 0.7071 0.7071

    """
    r = np.asarray(rotation, float)
    trace = r[0, 0] + r[1, 1] + r[2, 2]
    if trace > 0.0:
        s = 2.0 * math.sqrt(1.0 + trace)
        return ((r[2, 1] - r[1, 2]) / s, (r[0, 2] - r[2, 0]) / s, (r[1, 0] - r[0, 1]) / s,
                0.25 * s)
    i = int(np.argmax(np.diag(r)))
    j, k = (i + 1) % 3, (i + 2) % 3
    s = 2.0 * math.sqrt(1.0 + r[i, i] - r[j, j] - r[k, k])
    q = [0.0, 0.0, 0.0, (r[k, j] - r[j, k]) / s]
    q[i], q[j], q[k] = 0.25 * s, (r[j, i] + r[i, j]) / s, (r[k, i] + r[i, k]) / s
    return tuple(q)
