"""Rigid-body mass properties shared by the structures and the vehicle: inertia tensors from
YAML entries, their physical check, the parallel-axis theorem and composite bodies.

Units: mass [kg], positions [m], inertia tensors [kg m^2] about the centre of mass (tensor
entries, so a product entry is -integral(x z dm)).
"""
import numpy as np

from motoflex_ros.errors import ConfigError

__all__ = ["inertia_matrix", "check_inertia", "parallel_axis", "composite_inertia"]


def inertia_matrix(spec):
    """3x3 inertia tensor [kg m^2] from a mapping xx, yy, zz, xy, xz, yz (tensor entries)."""
    xy, xz, yz = spec.get("xy", 0.0), spec.get("xz", 0.0), spec.get("yz", 0.0)
    return np.array([[spec["xx"], xy, xz], [xy, spec["yy"], yz], [xz, yz, spec["zz"]]], float)


def check_inertia(tensor, source, key):
    """Raise ConfigError unless the tensor is positive definite with principal moments that
    satisfy the triangle inequality (I1 + I2 >= I3 for every ordering)."""
    moments = np.linalg.eigvalsh(tensor)
    if moments[0] <= 0.0:
        raise ConfigError(source, key, "inertia tensor is not positive definite (principal "
                                       f"moments {np.round(moments, 6).tolist()} kg m^2)")
    if moments[0] + moments[1] < moments[2] * (1.0 - 1e-9):
        raise ConfigError(source, key, "inertia tensor violates the triangle inequality "
                                       f"(principal moments {np.round(moments, 6).tolist()}: "
                                       "I1 + I2 must be >= I3)")


def parallel_axis(mass, offset):
    """Parallel-axis (Steiner) term m (|d|^2 1 - d d^T) [kg m^2].

    What a point mass ``mass`` [kg] at ``offset`` d [m] from a reference point adds to an
    inertia tensor about that point.
    """
    d = np.asarray(offset)
    return mass * ((d @ d) * np.eye(3) - np.outer(d, d))


def composite_inertia(items):
    """Mass [kg], centre of mass [m] and inertia tensor about it [kg m^2] of rigid items.

    Parameters
    ----------
    items : iterable of (mass, com, inertia)
        Each item's mass [kg], centre of mass [m] and inertia tensor about its own centre of
        mass [kg m^2], all in one frame.

    Returns
    -------
    mass, com, inertia
        Total mass, common centre of mass c = sum m_i c_i / m, and
        I = sum (I_i + :func:`parallel_axis` (m_i, c_i - c)).

    """
    items = list(items)
    mass = sum(m for m, _, _ in items)
    com = sum(m * np.asarray(c) for m, c, _ in items) / mass
    inertia = np.zeros((3, 3))
    for m, c, own in items:
        inertia += own + parallel_axis(m, np.asarray(c) - com)
    return mass, com, inertia
