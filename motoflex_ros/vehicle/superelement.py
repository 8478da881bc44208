"""Craig-Bampton superelements: a clamped component's reduced model inside the vehicle.

The flexible ground truth of the paper (Sect. 4.1, Appendix: flexible bodies reduced by
Craig-Bampton, floating frame of reference) with the same reduced model the bench measured
(:meth:`Component.clamped_reduced`: same modes, same modal damping). The component's clamp nodes
are welded to a parent body; its loaded end carries what hangs from the component in the
vehicle (the steering joint on the frame's steering head, a wheel on the front assembly's or
swingarm's axle).

Coordinates x = (u_end [m], theta_end [rad], eta [-]): the loaded end's translation and small
rotation relative to the parent (realised in the engine as a chain of three prismatic and three
revolute coordinates through q0, exact to first order) and the fixed-interface modal
amplitudes. Linearized about straight running (parent translating at v, no rotation, x = 0),
the superelement adds to the equations of motion, with a_P = (alpha, a_0 + omega x v_0) the
parent's acceleration field at the world origin:

    elastic rows:  M_xx x'' + M_xR a_P + C_xx x' + K_xx x - M_v^T R_P^T g
    parent rows:   J_P^T (M_Rx x'') - J_w^T ((R_P M_v x) x g)

M_xR = T^T M Gamma couples elastic and rigid motion (Gamma: the rigid-motion field of the
component's nodes, columns omega then v_0), M_v its translational part (the static moment of
the elastic displacement), g the gravity vector [m/s^2]. The rigid-body mass of the component
stays with the vehicle's rigid bodies, which already carry it, so total mass, centre of mass and
inertia equal the rigid motorcycle's by construction.

Per-body rigid motion (the paper's flexible bodies, Appendix, Table A.1): a component is
several bodies (:mod:`motoflex_ros.structures.bodies`) and each moves rigidly with the vehicle
body that holds it, not all with the parent: the front assembly's fork bridge and stanchions
with the upper fork (steered, on the head joint), its lower fork with the lower fork, its
longitudinal arm with the arm (on its pivot in the frame: it does not steer). Gamma is then
taken per vehicle body P (the rows of the nodes that follow P), M_xR = sum_P T^T M Gamma_P, and
the coupling and gravity terms above are summed over those bodies, each with its own frame
(``follows`` of :func:`superelement_of`). The elastic coordinates and their end chain stay
those of the clamped component, relative to ``parent``.
"""
from dataclasses import dataclass, replace

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from motoflex_ros.errors import ModelError
from motoflex_ros.spatial import cross
from motoflex_ros.structures.assembly import rigid_field
from motoflex_ros.structures.bodies import split_bodies
from motoflex_ros.structures.clamped import reduce_clamped
from motoflex_ros.structures.craig_bampton import F_MAX_HZ, N_MODES
from motoflex_ros.vehicle.model import Body, Joint

__all__ = ["Superelement", "BoundSuperelement", "superelement_of", "coordinate_names",
           "end_body", "chain_parts", "generalized_residual", "follower_masks", "bushing"]


@dataclass(frozen=True)
class Superelement:
    """A component's clamped Craig-Bampton model placed in the vehicle.

    name; parent: body its clamps are welded to and its end chains hang from; end_point q0 [m]
    (vehicle frame) of the one loaded end; M, K, C (n_x square, [kg], [N/m], [N s/m] and mixed
    units by coordinate); couplings: ((body, M_xR_P), ...) the (n_x, 6) coupling with the
    (omega, v_0) field of each vehicle body P its nodes follow; n_modes fixed-interface modes
    after the end DOFs.

    ``ends`` None: one loaded end at ``end_point`` (coordinates and end body named as
    :func:`coordinate_names` and :func:`end_body` say). ``ends`` a tuple of (label, point [m])
    pairs: several interface nodes ("ends", e.g. a flexible body of
    :mod:`motoflex_ros.vehicle.flexible_bodies` with its joint points), x = (u_1, theta_1,
    u_2, theta_2, ..., eta), each end with its own six-joint chain through its point and its
    own massless end body ``end_body(se, label)``; ``end_point`` is then the reference node
    where the element is clamped to ``parent`` (the chains do not use it). The residual is the
    same for any number of ends: the end DOFs are rows of x.
    """

    name: str
    parent: str
    end_point: np.ndarray
    M: np.ndarray
    K: np.ndarray
    C: np.ndarray
    couplings: tuple
    n_modes: int
    ends: tuple = None

    @property
    def M_xR(self):
        """Coupling (n_x, 6) with one rigid motion of the whole component [kg, kg m]."""
        return sum(m for _, m in self.couplings)

    @property
    def n(self):
        """Number of elastic coordinates (6 per end + modes)."""
        return self.K.shape[0]

    @property
    def end_labels(self):
        """Labels of the ends, in coordinate order ((None,) for the one loaded end)."""
        return (None,) if self.ends is None else tuple(label for label, _ in self.ends)

    def end_points(self):
        """{label: point [m]} of the ends (label None for the one loaded end)."""
        if self.ends is None:
            return {None: np.asarray(self.end_point, float)}
        return {label: np.asarray(point, float) for label, point in self.ends}

    def loop_coordinates(self):
        """Coordinates the engine solves first from a loop closing on this element: all of a
        massless element's (a bushing, :func:`bushing`), none of one with mass."""
        return () if np.any(self.M) else tuple(coordinate_names(self))

    def bind(self, tree):
        """The element placed in a compiled tree: its coordinates and the frames of the bodies
        its nodes follow looked up once (force-element hook of the engine, see
        ``VehicleModel.elements``)."""
        names = coordinate_names(self)
        indices = np.array([tree.index(n) for n in names], int)
        frames = tuple(tree.body_frames[body] for body, _ in self.couplings)
        return BoundSuperelement(self, indices, frames,
                                 tuple(np.array(m) for _, m in self.couplings), tuple(names))

    def scaled(self, factor):
        """The same superelement with stiffness multiplied by ``factor`` (rigid-limit checks)."""
        return replace(self, K=self.K * factor, C=self.C * factor)


@dataclass(frozen=True)
class BoundSuperelement:
    """A Superelement in a compiled tree: ``indices`` of its engine coordinates
    (:func:`coordinate_names` order, ``names`` their names), the frame index of each body its
    nodes follow and the coupling M_xR_P with each (same order)."""

    element: Superelement
    indices: np.ndarray
    frames: tuple
    couplings: tuple
    names: tuple = ()

    def generalized_residual(self, system, frames, q, u, udot):
        """Force-element hook of the engine (see :func:`generalized_residual`)."""
        return generalized_residual(self, system, frames, q, u, udot)


def _assembled_field(asm, gamma_nodes):
    """A node field (6 n_nodes, 6) on the assembled DOFs: Gamma_asm with expand @ Gamma_asm =
    Gamma_nodes (least squares: exact for a rigid field)."""
    normal = (asm.expand.T @ asm.expand).tocsc()
    # coordinates that move no node (a superelement's generalized coordinates): zero there
    empty = np.flatnonzero(normal.diagonal() == 0.0)
    if len(empty):
        normal = normal + sp.csc_matrix((np.ones(len(empty)), (empty, empty)),
                                        shape=normal.shape)
    return spla.spsolve(normal, asm.expand.T @ gamma_nodes).reshape(-1, 6)


def follower_masks(component, parent, follows):
    """{vehicle body: node mask} of the component's nodes: the nodes of each of its bodies
    (:func:`~motoflex_ros.structures.bodies.split_bodies`) that holds a node named in
    ``follows[body]`` follow that body, all others ``parent``."""
    owner = np.full(len(component.node_xyz), parent, dtype=object)
    if follows and getattr(component, "structure", None) is None:
        where = getattr(component, "source", "") or component.name
        raise ModelError(f"{where}: component '{component.name}' is a superelement (matrices "
                         "only, no members), so the flexible motorcycle cannot tell which of "
                         "its nodes move with the vehicle bodies "
                         f"{', '.join(sorted(follows))}; give its beam or mesh model instead")
    groups = split_bodies(component.structure) if follows else []
    for body, node_names in (follows or {}).items():
        for name in node_names:
            if name not in component.node_names:
                raise ModelError(f"component '{component.name}': no node '{name}' to say which "
                                 f"of its bodies follows the vehicle body '{body}'")
            group = next(g for g in groups if component.node_names[name] in g)
            owner[list(group)] = body
    order = [parent] + sorted({str(b) for b in owner} - {parent})
    return {body: owner == body for body in order}


def superelement_of(component, parent, n_modes=N_MODES, f_max_hz=F_MAX_HZ, zeta=None,
                    follows=None):
    """Superelement of a structures Component welded to body ``parent`` at its clamps.

    The reduced matrices are those of ``component.clamped_reduced(n_modes, f_max_hz, zeta)``
    (``zeta`` None: the component's own damping_ratio);
    node positions are taken in the vehicle frame (placement origin + component frame).
    ``follows``: {vehicle body: [node names]}: the component's bodies holding those nodes move
    rigidly with that vehicle body (module docstring); the others with ``parent``.
    """
    cb, asm = component.craig_bampton(n_modes, f_max_hz, zeta)
    keep, end_dofs = component.clamped_coordinates(cb)
    if end_dofs[0] != 0:
        raise ModelError(f"component '{component.name}': the loaded end must be the first "
                         "interface node after the clamps")
    reduced = reduce_clamped(component.name, cb, keep, end_dofs, component.q0, asm.expand)
    gamma_nodes = rigid_field(component.node_xyz + component.origin)
    transform = cb.transform[:, keep]
    mass = asm.M if sp.issparse(asm.M) else sp.csr_matrix(asm.M)
    couplings = []
    for body, mask in follower_masks(component, parent, follows).items():
        gamma = _assembled_field(asm, gamma_nodes * np.repeat(mask, 6)[:, None])
        couplings.append((body, np.asarray(transform.T @ (mass @ gamma))))
    return Superelement(component.name, parent, component.origin + component.q0, reduced.M,
                        reduced.K, reduced.C, tuple(couplings), cb.n_modes)


_END_DOFS = ("ux", "uy", "uz", "rx", "ry", "rz")
_UNIT = np.eye(3)


def coordinate_names(se):
    """Engine coordinate names of a superelement: six DOFs per end, then the modal amplitudes
    (one loaded end: name_ux .. name_rz; several: name_label_ux .. name_label_rz per end)."""
    names = []
    for label in se.end_labels:
        prefix = se.name if label is None else f"{se.name}_{label}"
        names += [f"{prefix}_{d}" for d in _END_DOFS]
    return names + [f"{se.name}_eta{i}" for i in range(se.n - len(names))]


def end_body(se, label=None):
    """Name of the (massless) body that moves with the superelement's loaded end (``label``
    None), or with its end ``label`` (a superelement with several ends)."""
    if se.ends is None:
        if label is not None:
            raise ModelError(f"superelement '{se.name}' has one loaded end; it has no end "
                             f"'{label}'")
        return f"{se.name}_end"
    if label not in se.end_labels:
        raise ModelError(f"superelement '{se.name}' has no end '{label}' (ends: "
                         f"{', '.join(map(str, se.end_labels)) or 'none'})")
    return f"{se.name}_{label}_end"


def chain_parts(se):
    """Massless bodies and joints that realise the elastic coordinates in the engine.

    End DOFs: for each end, prismatic along x, y, z then revolute about x, y, z, all through
    that end's point and hanging from ``parent`` (exact to first order: the linearization sees
    u_end and theta_end, the end's motion relative to the parent). Modal amplitudes:
    'modal' joints (coordinates that move no frame); their inertia, stiffness and damping come
    from the element's residual.
    """
    names = coordinate_names(se)
    points = se.end_points()
    n_end = 6 * len(points)
    bodies, joints = [], []
    parent = se.parent
    for i, name in enumerate(names):
        if i < n_end:
            label, dof = se.end_labels[i // 6], i % 6
            point = points[label]
            parent = se.parent if dof == 0 else parent
            child = end_body(se, label) if dof == 5 else f"{name}_body"
            kind, axis = ("prismatic" if dof < 3 else "revolute"), _UNIT[dof % 3]
        else:
            kind, axis, point = "modal", np.zeros(3), np.asarray(se.end_point, float)
            parent, child = se.parent, f"{name}_body"
        bodies.append(Body(child, 0.0, point.copy(), np.zeros((3, 3))))
        joints.append(Joint(name, kind, parent, child, axis, point.copy()))
        parent = child
    return bodies, joints


def bushing(name, parent, point, K6, C6=None):
    """A compliant joint ("bushing") as a massless superelement with one end and no modes.

    A 6 x 6 spring between two bodies at ``point`` [m] (vehicle frame): K6 [N/m, N m/rad and
    N/rad, N m/m off the diagonal blocks] on x = (u, theta), the translation [m] and small
    rotation [rad] of its end body relative to ``parent`` at the point, in the reference axes;
    C6 [N s/m, N m s/rad] (None: no damping). M = 0 and no coupling: the bushing carries no
    mass. Place it with :func:`chain_parts` and close its end body (:func:`end_body`) onto the
    other body with a fixed cut joint, or hang the other body from it as a fixed tree child.
    A direction of zero stiffness is allowed where a loop determines it (its coordinate is then
    dependent); an independent coordinate with neither mass nor stiffness is refused by the
    linearization (:func:`~motoflex_ros.vehicle.linearize.linearize_at`), naming the bushing.
    """
    K6 = np.asarray(K6, float)
    C6 = np.zeros((6, 6)) if C6 is None else np.asarray(C6, float)
    for what, matrix in (("K6", K6), ("C6", C6)):
        if matrix.shape != (6, 6) or not np.allclose(matrix, matrix.T, rtol=0.0,
                                                     atol=1e-12 * np.max(np.abs(matrix))):
            raise ModelError(f"bushing '{name}': {what} must be a symmetric 6 x 6 matrix "
                             f"(got shape {matrix.shape})")
    return Superelement(name, parent, np.asarray(point, float).copy(), np.zeros((6, 6)), K6,
                        C6, (), 0)


def generalized_residual(bound, system, frames, q, u, udot):
    """The superelement's terms of the residual (module docstring), over all coordinates.

    ``bound``: a :class:`BoundSuperelement` (``Superelement.bind(tree)``), so that no name is
    looked up here, on the hot path of the linearization.
    """
    se, idx = bound.element, bound.indices
    g = np.array([0.0, 0.0, -system.model.gravity])
    x, xd, xdd = q[idx], u[idx], udot[idx]
    out = np.zeros(len(u), np.result_type(q, u, udot, *(frames[i].R for i in bound.frames)))
    out[idx] = se.M @ xdd + se.C @ xd + se.K @ x
    for frame, m_xr in zip(bound.frames, bound.couplings):
        f = frames[frame]
        alpha = f.Jw @ udot + f.dw
        a0 = f.Jv @ udot + f.dv0 + cross(f.w, f.v0)
        m_v = m_xr[:, 3:].T
        out[idx] += m_xr @ np.concatenate([alpha, a0]) - m_v.T @ (f.R.T @ g)
        wrench = m_xr.T @ xdd
        moment = cross(f.R @ (m_v @ x), g)
        out += f.Jw.T @ (wrench[:3] - moment) + f.Jv.T @ wrench[3:]
    return out
