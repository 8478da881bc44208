"""Rolling contact of a toroidal tyre on flat ground (crown radius, contact frame, slip).

Contact point, for a wheel with centre c, unit spin axis a, rolling radius r and crown radius
r_c on ground with upward normal n (docs/vehicle-engine.md):

    rho = (r - r_c) e + r_c d,   P = c + rho

with d = -n and e the unit vector in the wheel plane pointing to the ground,
e = (d - (d.a) a)/|d - (d.a) a|. The contact frame: longitudinal t = (a x n)/|a x n|, lateral
l = n x t, normal n. The material point of the wheel at P has velocity v_P = J_P u. Its
acceleration along the moving contact point is d/dt v_P = v0' + w' x P + w x P', where P' is
the geometric velocity of the contact point, which moves around the rim and across the crown
(P' = c' + rho'), not the velocity of a material point.
"""
from dataclasses import dataclass

import numpy as np

from motoflex_ros.spatial import cross, unit

__all__ = ["ContactState", "contact_state", "GROUND_NORMAL"]

GROUND_NORMAL = np.array([0.0, 0.0, 1.0])


@dataclass(frozen=True)
class ContactState:
    """Contact point P [m], contact frame (t, l, n) and its rates, material velocity Jacobian J
    (3 x n) and velocity v [m/s] of the wheel point at P, its bias acceleration a_bias [m/s^2]
    along the moving contact point, and the camber angle leaning left [rad]."""

    P: np.ndarray
    t: np.ndarray
    l: np.ndarray
    t_dot: np.ndarray
    l_dot: np.ndarray
    J: np.ndarray
    v: np.ndarray
    a_bias: np.ndarray
    camber: complex

    @property
    def height(self):
        """Height of the contact point above the ground [m]."""
        return self.P[2]

    def row(self, direction):
        """Constraint row (1 x n) and its bias d/dt(row) u for 'long', 'lat' or 'normal'."""
        if direction == "normal":
            return GROUND_NORMAL @ self.J, GROUND_NORMAL @ self.a_bias
        k, k_dot = (self.t, self.t_dot) if direction == "long" else (self.l, self.l_dot)
        return k @ self.J, k_dot @ self.v + k @ self.a_bias


def _contact_offset(a, a_dot, radius, crown):
    d = -GROUND_NORMAL
    p = d - (d @ a) * a
    p_dot = -(d @ a_dot) * a - (d @ a) * a_dot
    e = unit(p)
    e_dot = (p_dot - e * (e @ p_dot)) / np.sqrt(p @ p)
    return (radius - crown) * e + crown * d, (radius - crown) * e_dot


def _heading(a, a_dot):
    w = cross(a, GROUND_NORMAL)
    w_dot = cross(a_dot, GROUND_NORMAL)
    t = unit(w)
    t_dot = (w_dot - t * (t @ w_dot)) / np.sqrt(w @ w)
    return t, t_dot, cross(GROUND_NORMAL, t), cross(GROUND_NORMAL, t_dot)


def contact_state(wheel, frame, u):
    """ContactState of ``wheel`` whose frame state (kinematics.FrameState) is ``frame``."""
    a = frame.R @ wheel.axis
    a_dot = cross(frame.w, a)
    centre = frame.R @ wheel.centre + frame.t
    centre_dot = frame.v0 + cross(frame.w, centre)
    rho, rho_dot = _contact_offset(a, a_dot, wheel.radius, wheel.crown_radius)
    P = centre + rho
    J = frame.point_velocity_jacobian(P)
    v = J @ u
    a_bias = frame.dv0 + cross(frame.dw, P) + cross(frame.w, centre_dot + rho_dot)
    t, t_dot, l, l_dot = _heading(a, a_dot)
    return ContactState(P, t, l, t_dot, l_dot, J, v, a_bias, -np.arcsin(a @ GROUND_NORMAL))
