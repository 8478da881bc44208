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
    """Eq. (1): a4 = -(a1 x_q + a2 y_q + a3 z_q) of the deformed plane n.x + a4 = 0 [m].

    Parameters
    ----------
    n : array (3,)
        Unit normal (a1, a2, a3) of the deformed symmetry plane, n = R_y [-].
    q : array (3,)
        Loaded end position, loaded [m].

    Returns
    -------
    float
        Plane offset a4 [m].

    Examples
    --------
    The symmetry plane moved sideways by 2 mm without turning, y = 0.002, has a4 = -0.002 m:

    >>> plane_offset([0.0, 1.0, 0.0], [1.0, 0.002, 0.5])
    -0.002

    """
    return -float(np.dot(n, q))


def joint_position(n, a4, q0):
    """Eqs. (2)-(4): the joint (x_j, z_j) [m] where the deformation axis meets the line O-q0.

    The axis is the deformed symmetry plane at y = 0: a1 x + a3 z + a4 = 0 (eq. 2). Substituting
    z = (z_q0 / x_q0) x gives eq. (3) x_j = -a4 / (a1 + a3 z_q0 / x_q0) and eq. (4). It is
    evaluated here along the unit vector e0 = (x_q0, z_q0)/L, x_j = s e0_x, z_j = s e0_z with
    s = -a4 / (a1 e0_x + a3 e0_z), which is the same point and stays finite when x_q0 = 0.

    Parameters
    ----------
    n : array (3,)
        Unit normal of the deformed symmetry plane, n = R_y [-].
    a4 : float
        Plane offset [m] (eq. 1).
    q0 : array (3,)
        Loaded end, unloaded [m].

    Returns
    -------
    (float, float)
        x_j, z_j [m].

    Examples
    --------
    A turn of theta about the vertical axis through (0.4, 0, 0), load at q0 = (1, 0, 0): the
    plane normal is (-sin theta, cos theta, 0), its offset a4 = 0.4 sin theta, and the joint is
    back at x = 0.4 m whatever theta:

    >>> theta = 0.01
    >>> n = [-np.sin(theta), np.cos(theta), 0.0]
    >>> x_j, z_j = joint_position(n, 0.4 * np.sin(theta), [1.0, 0.0, 0.0])
    >>> round(float(x_j), 12), round(float(z_j), 12)
    (0.4, 0.0)

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

    Parameters
    ----------
    x_j, z_j : float
        The joint in the component's x-z plane [m] (eqs. 3-4).
    q0 : array (3,)
        Loaded end, unloaded [m].

    Returns
    -------
    float
        l [m], negative when the joint lies behind O.

    Examples
    --------
    q0 = (3, 0, 4) m: a joint at (0.3, 0, 0.4) is 0.5 m from O towards q0, one at
    (-0.3, 0, -0.4) is 0.5 m behind it:

    >>> float(joint_distance(0.3, 0.4, [3.0, 0.0, 4.0]))
    0.5
    >>> float(joint_distance(-0.3, -0.4, [3.0, 0.0, 4.0]))
    -0.5

    """
    length = np.hypot(q0[0], q0[2])
    return (x_j * q0[0] + z_j * q0[2]) / length


def axis_angle(n, q0):
    """Eq. (6): beta = atan(-a1/a3) - atan(z_q0/x_q0), wrapped into [0, pi) [rad].

    The axis direction in the x-z plane is (a3, -a1); atan2 of it differs from atan(-a1/a3) by
    a multiple of pi, which the wrapping removes, so the result is eq. (6) exactly.

    Parameters
    ----------
    n : array (3,)
        Unit normal of the deformed symmetry plane, n = R_y [-].
    q0 : array (3,)
        Loaded end, unloaded [m].

    Returns
    -------
    float
        beta [rad] in [0, pi).

    Examples
    --------
    A small turn theta about the axis a = (cos 30 deg, 0, sin 30 deg) moves the normal from e_y
    to e_y + theta a x e_y = (-theta sin 30 deg, 1, theta cos 30 deg); with q0 on the x axis
    beta is 30 deg, and the opposite turn gives the same axis:

    >>> theta, a = 1e-3, np.radians(30.0)
    >>> q0 = [1.0, 0.0, 0.0]
    >>> round(float(np.degrees(axis_angle([-theta * np.sin(a), 1.0, theta * np.cos(a)], q0))), 9)
    30.0
    >>> round(float(np.degrees(axis_angle([theta * np.sin(a), 1.0, -theta * np.cos(a)], q0))), 9)
    30.0

    """
    theta_j = np.arctan2(-n[0], n[2])
    theta_0 = np.arctan2(q0[2], q0[0])
    return float(np.mod(theta_j - theta_0, np.pi))


def moment_arm(l, beta, q0):
    """Eq. (7): b = (L - l) sin(beta), L = sqrt(x_q0^2 + z_q0^2) [m].

    Parameters
    ----------
    l : float
        Joint distance from O along O-q0 [m] (eq. 5).
    beta : float
        Axis angle to the line O-q0 [rad] (eq. 6).
    q0 : array (3,)
        Loaded end, unloaded [m].

    Returns
    -------
    float
        b [m], the distance of q0 from the axis (signed with sin(beta)).

    Examples
    --------
    L = 1 m, joint at 0.4 m: an axis across O-q0 has the arm 0.6 m, one at 30 deg half of it:

    >>> q0 = [0.6, 0.0, 0.8]
    >>> round(float(moment_arm(0.4, np.pi / 2, q0)), 12)
    0.6
    >>> round(float(moment_arm(0.4, np.pi / 6, q0)), 12)
    0.3

    """
    length = np.hypot(q0[0], q0[2])
    return (length - l) * np.sin(beta)


def axis_stiffness(force, y_q, b):
    """Eq. (8): k = F_st b / asin(y_qst / b) [N m/rad], F_st [N], y_qst [m], b [m].

    Parameters
    ----------
    force : float
        Static lateral load F_st at q0 [N].
    y_q : float
        Lateral displacement y_qst of the loaded end under it [m].
    b : float
        Moment arm of the load about the axis [m] (eq. 7).

    Returns
    -------
    float
        k [N m/rad].

    Examples
    --------
    A spring k = 1e4 N m/rad with the arm b = 0.5 m under F = 100 N turns by
    theta = F b / k = 5 mrad, so the end moves y = b sin(theta); eq. (8) gives k back:

    >>> round(float(axis_stiffness(100.0, 0.5 * np.sin(0.005), 0.5)), 6)
    10000.0

    """
    return force * b / np.arcsin(y_q / b)


def deformation_axis(q, rotation, q0):
    """Eqs. (1)-(7) from the loaded end's position q [m] and orientation R (3x3).

    ``q`` and ``q0`` are in the component frame (clamp at O, symmetry plane x-z). Returns a
    :class:`DeformationAxis`. An axis parallel to the line O-q0 (within PARALLEL_TOL, e.g. a
    straight tube twisting about itself) has no joint on that line: l, x_j, z_j are NaN and b is
    the distance of q0 from the axis.

    Parameters
    ----------
    q : array (3,)
        Loaded end position, loaded [m].
    rotation : array (3, 3)
        Loaded end orientation R [-]; its second column is the plane normal n.
    q0 : array (3,)
        Loaded end, unloaded [m].

    Returns
    -------
    DeformationAxis
        l [m], beta [rad], b [m], x_j, z_j [m].

    Examples
    --------
    The end q0 = (1, 0, 0) turned by 0.01 rad about the vertical axis through (0.4, 0, 0):
    the joint is at l = 0.4 m, the axis across O-q0 (beta = pi/2) and the arm 0.6 m:

    >>> theta = 0.01
    >>> rot = np.array([[np.cos(theta), -np.sin(theta), 0.0],
    ...                 [np.sin(theta), np.cos(theta), 0.0], [0.0, 0.0, 1.0]])
    >>> q = np.array([0.4, 0.0, 0.0]) + rot @ [0.6, 0.0, 0.0]
    >>> axis = deformation_axis(q, rot, [1.0, 0.0, 0.0])
    >>> round(axis.l, 12), round(axis.beta / np.pi, 12), round(axis.b, 12)
    (0.4, 0.5, 0.6)

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
