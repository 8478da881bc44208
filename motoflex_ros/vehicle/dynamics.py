"""Equations of motion in residual form (Kane's method with numerical partial velocities).

State x = [q_r, u_i, z]: independent non-cyclic coordinates q_r (roll and the joint angles),
independent lateral speeds u_i (their rates, plus lateral velocity and yaw rate of the base when
the wheels run on tyres), and tyre states z (side force and aligning moment of each tyre). The
forward speed v is a parameter. Cyclic coordinates (x, y, yaw, wheel spins) are held at zero;
height and pitch of the base follow from the contact-height constraints (fixed-count Newton);
dependent speeds (z', pitch', spins and, for knife-edge wheels, y' and yaw') follow from the
rolling constraints G u = 0 and their accelerations from G u' + G' u = 0.

Residual R(x', x; v) = [q_r' - u(q_r);  S^T (sum J^T m a + J_w^T (I w' + w x I w) - Q);
tyre relaxation rows], S = du/du_i the partial velocities. E = dR/dx', A = -dR/dx.
"""
from dataclasses import dataclass

import numpy as np

from motoflex_ros.errors import ConfigError, ModelError
from motoflex_ros.vehicle.contact import GROUND_NORMAL, contact_state
from motoflex_ros.vehicle.kinematics import compile_tree, coordinate_names_of, frame_states
from motoflex_ros.vehicle.loops import loop_rows

__all__ = ["VehicleSystem", "build_system", "bind_elements", "residual", "positions",
           "dependent_speeds", "constraint_matrix", "generalized_force_residual",
           "KinematicState", "kinematic_state"]

_NEWTON_STEPS = 3
_LOOP_NEWTON_STEPS = 6      # loop closure is nonlinear in the joint angles away from x = 0
_RANK_TOL = 1e-8


@dataclass(frozen=True)
class VehicleSystem:
    """A compiled vehicle: tree, index partition, constraint list, state names and the model's
    force elements bound to the tree (:func:`bind_elements`)."""

    model: object
    tree: object
    indep_pos: tuple
    dep_pos: tuple
    indep_speed: tuple
    dep_speed: tuple
    constraints: tuple
    state_names: tuple
    elements: tuple = ()
    loop_dep: tuple = ()

    @property
    def n_states(self):
        """Number of states of the linear model."""
        return len(self.state_names)

    @property
    def n_tyre_states(self):
        """Two relaxed states (side force, aligning moment) per tyre."""
        return 2 * sum(w.tyre is not None for w in self.model.wheels)


def _partition(tree, wheels, loop_dep, base="floating"):
    """Index lists (indep_pos, dep_pos, indep_speed, dep_speed, rolling constraints).

    Floating base: roll and the joint coordinates are independent, height and pitch follow from
    the contact heights; on a fixed base (a mechanism on a stand) the base coordinates are held
    at zero and only joint coordinates remain. Coordinates solved from loop closures and locks
    (``loop_dep``) are dependent in position and speed.
    """
    idx = tree.index
    joints = [k for k, c in enumerate(tree.coordinates)
              if c.group == "joint" and k not in loop_dep]
    if base == "fixed":
        return joints, list(loop_dep), list(joints), list(loop_dep), []
    knife = [w for w in wheels if w.tyre is None]
    lateral_dep = [idx("y"), idx("yaw")][:len(knife)]
    spins = [k for k, c in enumerate(tree.coordinates) if c.group == "spin"]
    dep_speed = [idx("z"), idx("pitch"), *spins, *lateral_dep, *loop_dep]
    indep_pos = [idx("roll"), *joints]
    lateral_free = [k for k in (idx("y"), idx("yaw")) if k not in lateral_dep]
    indep_speed = [*lateral_free, *indep_pos]
    constraints = [(i, d) for i, w in enumerate(wheels)
                   for d in (("long", "lat", "normal") if w.tyre is None else ("long", "normal"))]
    return indep_pos, [idx("z"), idx("pitch"), *loop_dep], indep_speed, dep_speed, constraints


def _loop_description(tree):
    cuts = [c.joint.name for c in tree.cut_joints]
    locks = [c.name for c in tree.coordinates if c.locked]
    parts = [f"cut joints {', '.join(cuts)}" if cuts else "", f"locked {', '.join(locks)}"
             if locks else ""]
    return " and ".join(p for p in parts if p)


def _carrying_mass(model, tree, frames):
    """Mask of the coordinates that move a mass at the reference: a body with mass or inertia,
    or a frame a force element couples a mass to (a superelement's ``couplings``)."""
    moving = np.zeros(len(tree.coordinates), bool)
    carried = [item.frame for item in tree.masses if item.mass > 0 or np.any(item.inertia)]
    carried += [tree.body_frames[body] for element in model.elements
                for body, coupling in getattr(element, "couplings", ()) if np.any(coupling)]
    for frame in set(carried):
        f = frames[frame]
        moving |= np.any(f.Jw != 0, axis=0) | np.any(f.Jv != 0, axis=0)
    return moving


def _loop_dependent(model, tree, frames):
    """Coordinates solved from the loop-closure and lock constraints (coordinate partitioning).

    Locked coordinates first, then those a force element asks to be solved from its loop
    (``loop_coordinates()``: a massless bushing's, which would otherwise be independent
    coordinates without mass) unless they move a mass (a bushing that carries a body); then,
    greedily, joint coordinates in order of declaration whose constraint column adds rank
    (a coordinate named by a role, e.g. the steering angle, only when nothing else will do).
    Declaration order keeps the mechanism's own joints dependent and the coordinates a variant
    appends (lumped hinges, superelement end DOFs) independent.
    ConfigError when the constraints are redundant (rank below their count): a loop that is
    over-constrained.
    """
    G = loop_rows(tree, frames, np.zeros(len(tree.coordinates))).G
    if G.shape[0] == 0:
        return ()
    joints = [k for k, c in enumerate(tree.coordinates) if c.group == "joint"]
    sv = np.linalg.svd(G[:, joints], compute_uv=False)
    rank = int(np.sum(sv > _RANK_TOL * max(sv[0], 1e-300)))
    if rank < G.shape[0]:
        raise ConfigError(model.source, "joints",
                          f"redundant or over-constrained loop: {_loop_description(tree)} give "
                          f"{G.shape[0]} constraint equations of rank {rank}; make the "
                          f"mechanism exactly constrained (e.g. a spherical instead of a "
                          f"revolute joint where a planar loop closes)")
    roles = set(model.roles.values())
    declared = {name: i for i, joint in enumerate(model.joints)
                for name in coordinate_names_of(joint)}
    joints = sorted(joints, key=lambda k: (declared.get(tree.coordinates[k].name, len(declared)),
                                           k))
    locked = [k for k in joints if tree.coordinates[k].locked]
    preferred = {name for element in model.elements
                 for name in getattr(element, "loop_coordinates", tuple)()}
    carrying = _carrying_mass(model, tree, frames)
    first = [k for k in joints if k not in locked and not carrying[k]
             and tree.coordinates[k].name in preferred]
    others = [k for k in joints if k not in locked and k not in first]
    order = locked + first + [k for k in others if tree.coordinates[k].name not in roles]
    order += [k for k in others if tree.coordinates[k].name in roles]
    chosen, basis = [], np.zeros((G.shape[0], 0))
    for k in order:
        col = G[:, k]
        norm = np.linalg.norm(col)
        rest = col - basis @ (basis.T @ col)
        if norm > 1e-12 and np.linalg.norm(rest) > _RANK_TOL * norm:
            chosen.append(k)
            basis = np.column_stack([basis, rest / np.linalg.norm(rest)])
        if len(chosen) == G.shape[0]:
            break
    return tuple(sorted(chosen))


def _state_names(tree, indep_pos, indep_speed, wheels):
    names = [tree.coordinates[k].name for k in indep_pos]
    names += [f"{tree.coordinates[k].name}_rate" for k in indep_speed]
    for w in wheels:
        if w.tyre is not None:
            names += [f"{w.name}_side_force", f"{w.name}_aligning_moment"]
    return tuple(names)


def bind_elements(elements, tree):
    """Force elements ready for the residual: one with a ``bind(tree)`` method is replaced by
    what it returns (e.g. itself with its coordinate indices looked up once), others kept."""
    return tuple(e.bind(tree) if hasattr(e, "bind") else e for e in elements)


def build_system(model):
    """Compile a VehicleModel into a VehicleSystem and check the reference contact."""
    tree = compile_tree(model)
    n = len(tree.coordinates)
    frames = frame_states(tree, np.zeros(n), np.zeros(n))   # the reference configuration
    loop_dep = _loop_dependent(model, tree, frames)
    ip, dp, isp, dsp, cons = _partition(tree, model.wheels, loop_dep, model.base)
    if len(cons) + len(loop_dep) != len(dsp):
        raise ModelError(f"{model.source}: {len(cons)} rolling constraints for "
                         f"{len(dsp) - len(loop_dep)} dependent speeds; use two wheels, both "
                         "knife-edge or both tyred")
    system = VehicleSystem(model, tree, tuple(ip), tuple(dp), tuple(isp), tuple(dsp),
                           tuple(cons), _state_names(tree, ip, isp, model.wheels),
                           bind_elements(model.elements, tree), loop_dep)
    gap = loop_rows(tree, frames, np.zeros(n)).g
    if gap.size and np.max(np.abs(gap)) > 1e-9:
        raise ModelError(f"{model.source}: the loops ({_loop_description(tree)}) do not close "
                         f"in the reference configuration (largest gap {np.max(np.abs(gap)):.3g})")
    for wheel, f in zip(model.wheels, tree.wheel_frames):
        height = contact_state(wheel, frames[f], np.zeros(n)).height
        if abs(height) > 1e-6:
            raise ConfigError(model.source, f"wheels.{wheel.name}.centre",
                              f"the tyre does not touch the ground in the reference "
                              f"configuration (contact height {height:.6g} m; the centre height "
                              "must equal the radius)")
    return system


def _contacts(system, q, u):
    frames = frame_states(system.tree, q, u)
    contacts = [contact_state(w, frames[f], u)
                for w, f in zip(system.model.wheels, system.tree.wheel_frames)]
    return frames, contacts


def _solve_positions(system, q, steps=None):
    """Dependent coordinates from the contact heights and the loop closures (fixed-count
    Newton iteration, complex-step safe). ``steps`` None: enough for finite motions."""
    zero = np.zeros_like(q)
    dep = list(system.dep_pos)
    if not dep:
        return q
    if steps is None:
        steps = _LOOP_NEWTON_STEPS if system.loop_dep else _NEWTON_STEPS
    for _ in range(steps):
        frames, contacts = _contacts(system, q, zero)
        loops = loop_rows(system.tree, frames, q)
        values = [np.array([c.height for c in contacts]), loops.g]
        jac = [np.array([GROUND_NORMAL @ c.J[:, dep] for c in contacts]).reshape(-1, len(dep)),
               loops.G[:, dep]]
        q[dep] = q[dep] - np.linalg.solve(np.vstack(jac), np.concatenate(values))
    return q


def _constraint_rows(system, frames, contacts, q):
    """Velocity rows G (rolling, then loops and locks) and their bias (G u' + bias = 0)."""
    rows = [contacts[i].row(d) for i, d in system.constraints]
    loops = loop_rows(system.tree, frames, q)
    n = len(system.tree.coordinates)
    G = np.array([r for r, _ in rows]).reshape(-1, n)
    bias = np.array([b for _, b in rows])
    return np.vstack([G, loops.G]), np.concatenate([bias, loops.bias])


def constraint_matrix(system, q):
    """Velocity rows G (rolling, loops, locks) at coordinates q; they depend on q only."""
    zero = np.zeros_like(q)
    frames, contacts = _contacts(system, q, zero)
    return _constraint_rows(system, frames, contacts, q)[0]


def dependent_speeds(system, q, known):
    """All speeds u at coordinates q: ``known`` (n,) gives the forward speed and the
    independent speeds, the dependent ones follow from the rolling, loop and lock rows
    G u = 0."""
    return _solve_dependent(system, constraint_matrix(system, q), known)


def _solve_dependent(system, G, known, extra=0.0):
    dep = list(system.dep_speed)
    out = known.copy()
    out[dep] = np.linalg.solve(G[:, dep], -(G @ known) - extra)
    return out


def _partial_velocities(system, G):
    n = G.shape[1]
    S = np.zeros((n, len(system.indep_speed)), G.dtype)
    S[list(system.indep_speed), np.arange(len(system.indep_speed))] = 1.0
    dep = list(system.dep_speed)
    S[dep, :] = -np.linalg.solve(G[:, dep], G[:, list(system.indep_speed)])
    return S


def _cross_rows(a, b):
    """Cross products a x b along axis 1 of stacked vectors (m, 3) or stacked columns
    (m, 3, n), broadcast (complex-safe; numpy's cross costs ten times more on arrays this
    small)."""
    return np.stack([a[:, 1] * b[:, 2] - a[:, 2] * b[:, 1],
                     a[:, 2] * b[:, 0] - a[:, 0] * b[:, 2],
                     a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]], axis=1)


def generalized_force_residual(system, frames, u, udot):
    """Generalised inertia minus gravity forces: sum J^T m (a - g) + J_w^T (I w' + w x I w).

    Summed over the tree's mass items at once (each item's frame state stacked; a flexible
    motorcycle has about fifty): the same sum as item by item, a third of the residual's time
    fewer. Units: forces [N] on translations, moments [N m] on rotations."""
    masses = system.tree.masses
    g = np.array([0.0, 0.0, -system.model.gravity])
    on = [frames[item.frame] for item in masses]
    R = np.array([f.R for f in on])                                  # (m, 3, 3)
    Jw = np.array([f.Jw for f in on])                                # (m, 3, n)
    w, dw = np.array([f.w for f in on]), np.array([f.dw for f in on])
    com = np.array([item.com for item in masses])
    mass = np.array([item.mass for item in masses])
    c = np.einsum("mij,mj->mi", R, com) + np.array([f.t for f in on])
    # J_c = J_v - [c]x J_w: the velocity Jacobian of the point at c
    Jc = np.array([f.Jv for f in on]) - _cross_rows(c[:, :, None], Jw)
    acc = (Jc @ udot + np.array([f.dv0 for f in on]) + _cross_rows(dw, c)
           + _cross_rows(w, Jc @ u))
    inertia = R @ np.array([item.inertia for item in masses]) @ R.transpose(0, 2, 1)
    wdot = Jw @ udot + dw
    moment = (np.einsum("mij,mj->mi", inertia, wdot)
              + _cross_rows(w, np.einsum("mij,mj->mi", inertia, w)))
    return (np.einsum("min,mi->n", Jc, mass[:, None] * (acc - g))
            + np.einsum("min,mi->n", Jw, moment))


def _joint_spring_dampers(system, q, u):
    """Generalised forces of the joint springs and dampers, with the sign of a residual."""
    coords = system.tree.coordinates
    return np.array([c.stiffness * q[k] + c.damping * u[k] for k, c in enumerate(coords)])


def positions(system, x, newton_steps=None):
    """All coordinates q at the state x: independent ones from x, height and pitch of the base
    from the contact-height constraints and the loop coordinates from the loop closures
    (fixed-count Newton from q = 0). ``newton_steps`` None: enough for finite motions; 1 is
    exact for a complex-step perturbation of the reference, where q = 0 solves the
    constraints and one step gets the imaginary part to first order, which is all there is."""
    nq = len(system.indep_pos)
    q = np.zeros(len(system.tree.coordinates), np.result_type(x, float))
    q[list(system.indep_pos)] = x[:nq]
    return _solve_positions(system, q, newton_steps)


@dataclass(frozen=True)
class KinematicState:
    """What the residual needs of a state x besides x': coordinates q, speeds u, frame
    states, contact states and the velocity rows G with their bias (G u' + bias = 0)."""

    q: np.ndarray
    u: np.ndarray
    frames: list
    contacts: list
    G: np.ndarray
    bias: np.ndarray


def kinematic_state(system, x, v, q=None, G=None):
    """KinematicState at the state x and forward speed v [m/s]; q, G as in :func:`residual`.
    The residual is linear in x' at a fixed x: many x' at one x (the columns of E in the
    linearization) share one KinematicState."""
    n = len(system.tree.coordinates)
    nq, nu = len(system.indep_pos), len(system.indep_speed)
    q = positions(system, x) if q is None else q
    known = np.zeros(n, np.result_type(x, float))
    if system.model.base == "floating":
        known[0] = v
    known[list(system.indep_speed)] = x[nq:nq + nu]
    u = dependent_speeds(system, q, known) if G is None else _solve_dependent(system, G, known)
    frames, contacts = _contacts(system, q, u)
    G, bias = _constraint_rows(system, frames, contacts, q)
    return KinematicState(q, u, frames, contacts, G, bias)


def residual(system, xdot, x, v, applied=None, q=None, G=None, at=None):
    """Residual R(x', x; v) of the equations of motion (module docstring); v [m/s] > 0.

    applied: optional generalised forces on the coordinates (e.g. a steer torque [N m] on the
    steer joint's entry), subtracted like every applied force. q: the coordinates at x when
    already known (``positions(system, x)``), e.g. for many x' at one x; G: the velocity
    rows at that q when already known (:func:`constraint_matrix`); at: the whole
    :func:`kinematic_state` at x when already known (q and G are then not needed).
    """
    n = len(system.tree.coordinates)
    nq, nu = len(system.indep_pos), len(system.indep_speed)
    dtype = np.result_type(xdot, x, float)
    at = kinematic_state(system, x, v, q, G) if at is None else at
    q, u, frames, contacts, G = at.q, at.u, at.frames, at.contacts, at.G
    acc = np.zeros(n, dtype)
    acc[list(system.indep_speed)] = xdot[nq:nq + nu]
    udot = _solve_dependent(system, G, acc, at.bias)
    forces = generalized_force_residual(system, frames, u, udot)
    forces += _joint_spring_dampers(system, q, u)
    tyre_rows = _tyre_forces_and_rows(system, frames, contacts, xdot[nq + nu:], x[nq + nu:], v)
    forces = forces - tyre_rows[1]
    if applied is not None:
        forces = forces - applied
    for element in system.elements:
        forces = forces + element.generalized_residual(system, frames, q, u, udot)
    S = _partial_velocities(system, G)
    kin = xdot[:nq] - u[list(system.indep_pos)]
    return np.concatenate([kin, S.T @ forces, np.array(tyre_rows[0], dtype)])


def _tyre_forces_and_rows(system, frames, contacts, xdot_z, z, v):
    """Relaxation rows and the generalised force of the tyre side forces and moments."""
    n = len(system.tree.coordinates)
    rows = []
    force = np.zeros(n, np.result_type(z, frames[-1].R))
    k = 0
    for wheel, f, c in zip(system.model.wheels, system.tree.wheel_frames, contacts):
        tyre = wheel.tyre
        if tyre is None:
            continue
        F, M = z[k], z[k + 1]
        slip = c.l @ c.v
        sigma = tyre.relaxation_length(v)
        rows.append(sigma * xdot_z[k] + tyre.k_alpha * slip - v * (tyre.k_gamma * c.camber - F))
        rows.append(sigma * xdot_z[k + 1] - tyre.k_malpha * slip
                    - v * (tyre.k_mgamma * c.camber - M))
        force += c.J.T @ (F * c.l) + frames[f].Jw.T @ (M * GROUND_NORMAL)
        k += 2
    return rows, force
