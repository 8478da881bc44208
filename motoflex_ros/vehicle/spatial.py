"""Complex-step-safe vector helpers (no abs, norm or branching on values).

All functions accept real or complex arrays so that the residual of the equations of motion can
be differentiated by the complex-step method.
"""
import numpy as np

__all__ = ["cross", "skew", "unit", "rotation"]


def cross(a, b):
    """Cross product a x b of two 3-vectors (complex-safe)."""
    return np.array([a[1] * b[2] - a[2] * b[1],
                     a[2] * b[0] - a[0] * b[2],
                     a[0] * b[1] - a[1] * b[0]])


def skew(a):
    """Matrix [a]x with [a]x b = a x b."""
    return np.array([[0.0 * a[0], -a[2], a[1]],
                     [a[2], 0.0 * a[0], -a[0]],
                     [-a[1], a[0], 0.0 * a[0]]])


def unit(a):
    """Unit vector a / sqrt(a . a) (analytic continuation of the normalisation, complex-safe)."""
    return a / np.sqrt(a @ a)


def rotation(axis, angle):
    """Rotation matrix about the unit vector ``axis`` by ``angle`` [rad] (Rodrigues)."""
    k = skew(axis)
    return np.eye(3) + np.sin(angle) * k + (1.0 - np.cos(angle)) * (k @ k)
