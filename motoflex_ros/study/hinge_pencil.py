"""The linearized motorcycle with one lumped hinge per component, for any hinge, from one
linearization (the cheap evaluations of the hinge fit, :mod:`motoflex_ros.study.fitted`).

A lumped hinge of a component is a revolute joint through a point p along a unit axis a with
stiffness k and damping c, between the component's donor body and the body that carries what
the component carries (:mod:`motoflex_ros.vehicle.lumped`). Put in its place a chain of six
coordinates x = (u_x, u_y, u_z, phi_x, phi_y, phi_z) at the loaded end q0 (prismatic along x,
y, z, then revolute about x, y, z, intrinsic, all through q0; no springs), and linearize that
motorcycle once: E_c(v), A_c(v). The hinge is the chain constrained to x = g(theta),

    u(theta) = (R_a(theta) - 1) d,  R_x(phi_x) R_y(phi_y) R_z(phi_z) = R_a(theta),  d = q0 - p,

so that, with g' = g'(0) = (a x d, a) and g'' = g''(0) = ([a]x^2 d, phi''),
phi'' = (0, a_x a_z, 0) - (a_y a_z, 0, a_x a_y) (the second-order term of intrinsic XYZ angles
of a small rotation about a):

- every other row and column of the hinge motorcycle's E(v), A(v) is the chain motorcycle's
  with the chain's columns combined by g' (positions and rates alike);
- its hinge rows are the chain's dynamic rows combined by g'^T (virtual power) and its
  kinematic row the chain's combined by g'^T / |g'|^2 (theta' = omega);
- the hinge's stiffness row gets, besides -k and -c, the term -g'' . R_x(0), R_x(0) the chain's
  dynamic residual in straight running (the load the joint carries: the weight of what hangs
  from it): the second-order kinematics of the constraint (a geometric stiffness), the only
  second-order term, since in straight running the joint does not move.

This is exact, not a reduction: for the hinge a lumped variant builds, the pencils equal the
engine's direct linearization to rounding (test_study_fitted). R_x(0) does not depend on the
speed (checked at two speeds); the chain motorcycle's joint coordinates stay independent
(appended joints are, :func:`motoflex_ros.vehicle.dynamics._loop_dependent`).

The same chain with a full 6 x 6 spring K (and damper gamma K) on its six coordinates instead
of the hinge constraint is the lumped motorcycle with the component's whole end stiffness in the
hinge's place, massless (:meth:`HingePencil.spring_pencil`; K = C^-1, C the clamped FE model's
end compliance at q0: its static condensation on the loaded end). It tells how much of a
hinge's misfit is the single hinge (one deflection shape for every load) and how much the rest
of the lumped model (the hinge's place, the component's mass kept rigid). Linearized about the
undeflected chain: the springs' deflection under the straight-running load (K^-1 R_x(0), below
1e-4 m and rad here) is left out.
"""
from dataclasses import dataclass, replace

import numpy as np

from motoflex_ros.errors import ModelError
from motoflex_ros.spatial import skew
from motoflex_ros.study.identified_variants import GAMMA, build_variant
from motoflex_ros.vehicle import lumped
from motoflex_ros.vehicle.dynamics import build_system, residual
from motoflex_ros.vehicle.linearize import linearize
from motoflex_ros.vehicle.model import Body, Joint

__all__ = ["HingePencil", "hinge_second_order", "chain_vehicle", "CHAIN_BASE"]

CHAIN_BASE = "static"
"""The lumped variant whose motorcycle the chain replaces the hinge of: the static models'
inertia distribution (Sect. 5.2: front assembly's lower fork on the new body), c = gamma k."""

_UNIT = np.eye(3)
_CHECK_SPEEDS = (10.0, 40.0)


def hinge_second_order(axis, d):
    """(g', g'') (6,) of the hinge's chain coordinates x = g(theta) at theta = 0.

    ``axis`` unit a, ``d`` = q0 - p [m]: u = (R_a(theta) - 1) d and the intrinsic XYZ angles of
    R_a(theta) (module docstring). Units: g' [m/rad, -], g'' [m/rad^2, 1/rad].
    """
    a = np.asarray(axis, float)
    d = np.asarray(d, float)
    first = np.concatenate([np.cross(a, d), a])
    angles = np.array([-a[1] * a[2], a[0] * a[2], -a[0] * a[1]])
    second = np.concatenate([skew(a) @ skew(a) @ d, angles])
    return first, second


def _chain_names(component):
    return [f"{component}_chain_{n}" for n in ("ux", "uy", "uz", "rx", "ry", "rz")]


def chain_vehicle(model, component, hinge_name, q0):
    """``model`` with joint ``hinge_name`` replaced by the six-coordinate chain at q0 [m]."""
    hits = [i for i, j in enumerate(model.joints) if j.name == hinge_name]
    if not hits:
        raise ModelError(f"vehicle '{model.name}' has no joint '{hinge_name}' (component "
                         f"'{component}')")
    index = hits[0]
    hinge = model.joints[index]
    names = _chain_names(component)
    bodies, chain = list(model.bodies), []
    parent = hinge.parent
    for i, name in enumerate(names):
        child = hinge.child if i == 5 else f"{name}_body"
        if i < 5:
            bodies.append(Body(child, 0.0, np.array(q0, float), np.zeros((3, 3))))
        chain.append(Joint(name, "prismatic" if i < 3 else "revolute", parent, child,
                           _UNIT[i % 3].copy(), np.array(q0, float)))
        parent = child
    joints = list(model.joints)
    joints[index:index + 1] = chain
    return replace(model, bodies=tuple(bodies), joints=tuple(joints))


@dataclass(frozen=True, eq=False)
class _ChainSlots:
    """Where one component's chain sits in the chain motorcycle's states."""

    component: str
    q0: np.ndarray
    pos: np.ndarray          # state indices of the six chain coordinates
    rate: np.ndarray         # state indices of their rates
    load: np.ndarray         # R_x(0), the dynamic residual of the chain in straight running


class HingePencil:
    """E(v), A(v) of the motorcycle with one lumped hinge per component of ``names``, for any
    hinges, from one linearization of the chain motorcycle (module docstring).

    Parameters
    ----------
    vehicle : VehicleModel
        The rigid motorcycle.
    components, identified : mappings
        As :func:`motoflex_ros.study.identified_variants.build_variant` (the static variant is
        built to fix the inertia distribution and the hinge's place in the tree).
    names : sequence of str
        The flexible components.

    Attributes: ``names``, ``state_names`` (of the hinge motorcycle: the hinge coordinate of a
    component is called ``<component>_hinge``), ``base`` (the static variant's VehicleModel),
    ``E_coeffs``, ``A_coeffs`` (the chain motorcycle's speed polynomials).

    """

    def __init__(self, vehicle, components, identified, names):
        self.names = tuple(names)
        self.base = build_variant(vehicle, CHAIN_BASE, list(self.names), identified, components)
        model = self.base
        q0s = {}
        for name in self.names:
            site = lumped.site_of(components[name])
            q0s[name] = site.origin + site.q0
            model = chain_vehicle(model, name, f"{name}_{CHAIN_BASE}", q0s[name])
        system = build_system(model)
        lin = linearize(system)
        self.E_coeffs, self.A_coeffs = lin.E_coeffs, lin.A_coeffs
        states = list(system.state_names)
        loads = [residual(system, np.zeros(system.n_states), np.zeros(system.n_states), v)
                 for v in _CHECK_SPEEDS]
        if np.max(np.abs(loads[0] - loads[1])) > 1e-9 * max(np.max(np.abs(loads[0])), 1.0):
            raise ModelError(f"{model.name}: the loads of the hinge chains depend on the speed "
                             "in straight running; the hinge pencil assumes they do not")
        self.slots = []
        for name in self.names:
            chain = _chain_names(name)
            pos = np.array([states.index(c) for c in chain])
            rate = np.array([states.index(f"{c}_rate") for c in chain])
            # dynamic rows are ordered as the rate states (S^T forces over indep_speed)
            self.slots.append(_ChainSlots(name, q0s[name], pos, rate, loads[0][rate]))
        # reduced states: the chain's first coordinate (and rate) stands for the hinge's
        drop = {int(i) for s in self.slots for i in (*s.pos[1:], *s.rate[1:])}
        self._keep = np.array([i for i in range(len(states)) if i not in drop])
        renamed = {states[s.pos[0]]: f"{s.component}_hinge" for s in self.slots}
        renamed.update({states[s.rate[0]]: f"{s.component}_hinge_rate" for s in self.slots})
        self.state_names = tuple(renamed.get(states[i], states[i]) for i in self._keep)
        self._column = {int(i): k for k, i in enumerate(self._keep)}

    @property
    def n_states(self):
        """Number of states of the hinge motorcycle."""
        return len(self._keep)

    def _projections(self, hinges):
        """(T, T_left) (runs, n_chain, n_hinge) and the stiffness terms for a batch of hinges."""
        runs = len(hinges)
        n_chain, n = self.E_coeffs.shape[1], self.n_states
        right = np.zeros((runs, n_chain, n))
        right[:, self._keep, np.arange(n)] = 1.0
        left = right.copy()
        diag = np.zeros((runs, n, n))
        for s in self.slots:
            pos_col, rate_col = self._column[int(s.pos[0])], self._column[int(s.rate[0])]
            for r, run in enumerate(hinges):
                point, axis, k = run[s.component]
                first, second = hinge_second_order(axis, s.q0 - np.asarray(point, float))
                right[r, s.pos, pos_col] = first
                right[r, s.rate, rate_col] = first
                left[r, s.rate, rate_col] = first
                left[r, s.pos, pos_col] = first / (first @ first)
                diag[r, rate_col, pos_col] -= k + second @ s.load
                diag[r, rate_col, rate_col] -= GAMMA * k
        return right, left, diag

    def pencil(self, hinges, speeds):
        """(E, A), each (runs, speeds, n, n), of the hinge motorcycles at ``speeds`` [m/s].

        ``hinges``: a list (runs) of {component: (point [m], unit axis, k [N m/rad])} in the
        vehicle frame; c = gamma k (gamma = 0.001 s, the static models' damping).
        """
        e, a = self._chain_pencil(speeds)
        right, left, diag = self._projections(hinges)
        left_t = np.swapaxes(left, 1, 2)[:, None]
        e_h = left_t @ (e[None] @ right[:, None])
        a_h = left_t @ (a[None] @ right[:, None]) + diag[:, None]
        return e_h, a_h

    def _chain_pencil(self, speeds):
        speeds = np.atleast_1d(np.asarray(speeds, float))
        powers = speeds[:, None] ** np.arange(len(self.A_coeffs))[None, :]
        return (np.einsum("sp,pij->sij", powers, self.E_coeffs),
                np.einsum("sp,pij->sij", powers, self.A_coeffs))

    def spring_pencil(self, stiffness, speeds):
        """(E, A), each (speeds, n_chain, n_chain), of the chain motorcycle with a 6 x 6 spring
        on each component's chain (module docstring).

        ``stiffness``: {component: K (6, 6) at q0 in vehicle axes, rows and columns (u_x, u_y,
        u_z, theta_x, theta_y, theta_z) [N/m, N/rad, N m/m, N m/rad]}; damping gamma K.
        """
        e, a = self._chain_pencil(speeds)
        a = a.copy()
        for s in self.slots:
            k = np.asarray(stiffness[s.component], float)
            if k.shape != (6, 6) or not np.all(np.isfinite(k)):
                raise ModelError(f"component '{s.component}': the end stiffness must be a "
                                 "finite 6 x 6 matrix")
            a[:, s.rate[:, None], s.pos[None, :]] -= k
            a[:, s.rate[:, None], s.rate[None, :]] -= GAMMA * k
        return e, a
