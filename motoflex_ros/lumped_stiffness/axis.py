"""Deformation axis of a clamped component from the pose of its loaded end, eqs. (1)-(8).

Symbols (Passigato et al. 2023, Sect. 4.2.1-4.2.2, Fig. 2); the component frame has the clamp at
the origin O, the symmetry plane x-z and the lateral load F_y applied at the loaded end q0.

=========  ==========================================================  ==========
symbol     meaning                                                     unit
=========  ==========================================================  ==========
q0         loaded end, unloaded                                        m
q, R       loaded end position and orientation, loaded                 m, -
n          normal of the deformed symmetry plane, n = R_y              -
a4         plane offset, eq. (1)                                       m
x_j, z_j   revolute joint: axis meets the line O-q0, eqs. (3)-(4)      m
l          joint distance from O along O-q0 (signed), eq. (5)          m
beta       axis angle to the line O-q0, wrapped into [0, pi), eq. (6) rad
b          moment arm of the load about the axis, eq. (7)              m
k          rotational stiffness about the axis, eq. (8)                N m/rad
=========  ==========================================================  ==========
"""
from dataclasses import dataclass

import numpy as np

PARALLEL_TOL = 1e-9
"""An axis within this angle [rad] of the line O-q0 is parallel to it: it meets the line nowhere
(or everywhere), so l is undefined. Decided by a tolerance, not by an exact 0/0, whose outcome
depends on the BLAS kernel's round-off (the straight tube's torsion axis gave l = nan on Haswell
and Zen, l = 0.43 m on SkylakeX, Prescott and Sandybridge)."""

__all__ = ["DeformationAxis", "plane_offset", "joint_position", "joint_distance", "axis_angle",
           "moment_arm", "axis_stiffness", "deformation_axis", "axis_in_plane"]


@dataclass(frozen=True)
class DeformationAxis:
    """Joint position and orientation of a lumped stiffness model (eqs. 3-7).

    l [m], beta [rad] in [0, pi), b [m]; x_j, z_j [m] the joint in the component's x-z plane.
    """

    l: float
    beta: float
    b: float
    x_j: float
    z_j: float


def plane_offset(n, q):
    """Eq. (1): a4 = -(a1 x_q + a2 y_q + a3 z_q) of the deformed plane n.x + a4 = 0 [m]."""
    return -float(np.dot(n, q))


def joint_position(n, a4, q0):
    """Eqs. (2)-(4): the joint (x_j, z_j) [m] where the deformation axis meets the line O-q0.

    The axis is the deformed symmetry plane at y = 0: a1 x + a3 z + a4 = 0 (eq. 2). Substituting
    z = (z_q0 / x_q0) x gives eq. (3) x_j = -a4 / (a1 + a3 z_q0 / x_q0) and eq. (4). It is
    evaluated here along the unit vector e0 = (x_q0, z_q0)/L, x_j = s e0_x, z_j = s e0_z with
    s = -a4 / (a1 e0_x + a3 e0_z), which is the same point and stays finite when x_q0 = 0.
    """
    length = np.hypot(q0[0], q0[2])
    e0x, e0z = q0[0] / length, q0[2] / length
    s = -a4 / (n[0] * e0x + n[2] * e0z)
    return s * e0x, s * e0z


def joint_distance(x_j, z_j, q0):
    """Eq. (5): l = cos(atan(z_j/x_j) - atan(z_q0/x_q0)) sqrt(x_j^2 + z_j^2) [m].

    The cosine is +1 when the joint lies on the same side of O as q0 and -1 otherwise, so l is
    the signed distance of the joint from O along the direction of q0 (computed as a projection,
    which is identical and has no division by x).
    """
    length = np.hypot(q0[0], q0[2])
    return (x_j * q0[0] + z_j * q0[2]) / length


def axis_angle(n, q0):
    """Eq. (6): beta = atan(-a1/a3) - atan(z_q0/x_q0), wrapped into [0, pi) [rad].

    The axis direction in the x-z plane is (a3, -a1); atan2 of it differs from atan(-a1/a3) by
    a multiple of pi, which the wrapping removes, so the result is eq. (6) exactly.
    """
    theta_j = np.arctan2(-n[0], n[2])
    theta_0 = np.arctan2(q0[2], q0[0])
    return float(np.mod(theta_j - theta_0, np.pi))


def moment_arm(l, beta, q0):
    """Eq. (7): b = (L - l) sin(beta), L = sqrt(x_q0^2 + z_q0^2) [m]."""
    length = np.hypot(q0[0], q0[2])
    return (length - l) * np.sin(beta)


def axis_stiffness(force, y_q, b):
    """Eq. (8): k = F_st b / asin(y_qst / b) [N m/rad], F_st [N], y_qst [m], b [m]."""
    return force * b / np.arcsin(y_q / b)


def deformation_axis(q, rotation, q0):
    """Eqs. (1)-(7) from the loaded end's position q [m] and orientation R (3x3).

    ``q`` and ``q0`` are in the component frame (clamp at O, symmetry plane x-z). Returns a
    :class:`DeformationAxis`. An axis parallel to the line O-q0 (within PARALLEL_TOL, e.g. a
    straight tube twisting about itself) has no joint on that line: l, x_j, z_j are NaN and b is
    the distance of q0 from the axis.
    """
    q = np.asarray(q, dtype=float)
    q0 = np.asarray(q0, dtype=float)
    n = np.asarray(rotation, dtype=float)[:, 1]
    a4 = plane_offset(n, q)
    beta = axis_angle(n, q0)
    if _parallel_to_line(n, q0):
        # eq. (7) as beta -> 0 with the axis at distance d from the line O-q0: b -> |d|
        distance = abs(n[0] * q0[0] + n[2] * q0[2] + a4) / np.hypot(n[0], n[2])
        return DeformationAxis(l=float("nan"), beta=beta, b=float(distance),
                               x_j=float("nan"), z_j=float("nan"))
    x_j, z_j = joint_position(n, a4, q0)
    l = joint_distance(x_j, z_j, q0)
    return DeformationAxis(l=float(l), beta=beta, b=float(moment_arm(l, beta, q0)),
                           x_j=float(x_j), z_j=float(z_j))


def _parallel_to_line(n, q0):
    """True when the axis (direction (n_z, -n_x) in the x-z plane) is within PARALLEL_TOL of
    the line O-q0: the denominator of eq. (3), n . e0, vanishes relative to |n_xz|."""
    n_xz = np.hypot(n[0], n[2])
    across = abs(n[0] * q0[0] + n[2] * q0[2]) / np.hypot(q0[0], q0[2])
    return n_xz > 0 and across <= PARALLEL_TOL * n_xz


def axis_in_plane(axis, q0):
    """Point [m] and unit direction of a deformation axis in the component's x-z plane (3D).

    The joint is at l along O-q0; the direction is at angle beta from O-q0 (eqs. 5-6).
    """
    q0 = np.asarray(q0, dtype=float)
    theta = np.arctan2(q0[2], q0[0]) + axis.beta
    point = np.array([axis.x_j, 0.0, axis.z_j])
    return point, np.array([np.cos(theta), 0.0, np.sin(theta)])
