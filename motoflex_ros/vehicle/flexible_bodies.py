"""A beam component as the paper's flexible bodies in the engine: one superelement per body.

Paper, Appendix and Table A.1: each body of a component (frame; fork bridge, stanchions, lower
fork, longitudinal arm; lower link, upper link, wheel carrier) is reduced by Craig-Bampton with
its joint points as boundary nodes (:func:`~motoflex_ros.structures.bodies.reduce_bodies`) and
the reduced bodies are joined by joints. Here they are joined in the engine:

- a flexible body hangs from a vehicle body P (which carries its rigid motion and its mass) at
  a reference node: a :class:`~motoflex_ros.vehicle.superelement.Superelement` with several
  ends. Its coordinates x = (u_e, theta_e for each other boundary node e, eta): the body's
  reduced coordinates z = (u_b absolute, eta) with the reference node's six DOFs removed,
  z = Gamma rho + T_x x (rho the motion of P, Gamma the body's rigid field: columns
  (omega, v_0) on the boundary nodes, zero on the modes, exact because the constraint modes
  carry a rigid motion of the boundary with eta = 0). So M_xx = M_z[x, x], K_xx = K_z[x, x]
  (K_z Gamma = 0) and the coupling M_xR = M_z[x, :] Gamma, the superelement module's formula;
  P's rigid mass Gamma^T M_z Gamma is P's (give P
  :func:`~motoflex_ros.structures.bodies.body_mass_properties` of the body);
- a spring of the component between two bodies, or between a clamp node and a body, is a
  bushing (:func:`~motoflex_ros.vehicle.superelement.bushing`): K6 = the spring's 6 x 6 block
  in the axes the structure stores it (global axes of the component = vehicle axes), hung from
  the body at its first node, its end body closed onto the body at its second node by a fixed
  cut joint (the structure's spring joins two coincident nodes: zero length);
- a rigid link of the translations between two bodies is a spherical cut joint at the slave
  node (u_s = u_m + theta_m x (x_s - x_m), as the structure links them);
- a clamp node is welded to the vehicle body the caller names (the ground on the bench) by a
  fixed cut joint, or is the reference node of a body hanging from that body.

Damping (the paper's flexible bodies carry structural damping; one ratio per component):
stiffness-proportional, C = beta K for every body and every bushing, beta = 2 zeta / omega_1
[s], zeta the component's ``damping_ratio`` (the first one when it gives one per mode) and
omega_1 [rad/s] the first natural frequency of the component clamped (the joined bodies,
:func:`~motoflex_ros.structures.bodies.assemble_bodies`): the first clamped mode gets zeta,
mode i gets zeta omega_i / omega_1.

Bench (:func:`bench_model`): clamps welded to the ground, every body that holds no clamp on a
free rigid body (three prismatic and three revolute joints from the ground), gravity 0, base
'fixed'; its linearized M, K (:func:`~motoflex_ros.vehicle.linearize.mechanism_matrices`)
have the frequencies of the component-mode synthesis of
:func:`~motoflex_ros.structures.bodies.assemble_bodies` (test_flexible_bodies_bench).
"""
from dataclasses import dataclass, replace

import numpy as np

from motoflex_ros.errors import ModelError
from motoflex_ros.structures.assembly import rigid_field
from motoflex_ros.structures.bodies import assemble_bodies, body_mass_properties, reduce_bodies
from motoflex_ros.vehicle.model import Body, Joint, VehicleModel
from motoflex_ros.vehicle.superelement import Superelement, bushing, chain_parts, end_body

__all__ = ["OpenSpring", "BodyElements", "stiffness_damping_factor", "body_superelement",
           "body_elements", "add_to", "bench_model", "point_jacobian", "COINCIDENT_TOLERANCE"]

COINCIDENT_TOLERANCE = 1e-9
"""Largest distance [m] between the two nodes of a spring that becomes a bushing (a zero-length
element: the structure's springs join coincident nodes)."""

_AXES = np.eye(3)


@dataclass(frozen=True)
class OpenSpring:
    """A spring of the component the caller replaces by a vehicle joint: its nodes (names),
    the engine bodies that move with them, the point [m] (vehicle frame) and the 6 x 6 block
    [N/m, N m/rad] it would have been."""

    node1: str
    node2: str
    body1: str
    body2: str
    point: np.ndarray
    block: np.ndarray


@dataclass(frozen=True)
class BodyElements:
    """What :func:`body_elements` builds for one component.

    superelements: one multi-end Superelement per flexible body; bushings: one massless
    superelement per spring; bodies, joints: everything to add to a VehicleModel (the massless
    chain bodies and joints, bushings' first, then the cut joints: bushing closures, spherical
    links, clamp welds); node_bodies: {node name: engine body that moves with the node}
    (reference node: the vehicle body it hangs from; other boundary node: its end body), e.g.
    for a wheel on the loaded end; clamps: {clamp node name: engine body at the clamp};
    welded: {clamp node name: vehicle body it is welded to} (empty when no welds were asked);
    open_springs: springs left to the caller (:class:`OpenSpring`); beta [s] the stiffness
    factor of the damping (module docstring).
    """

    name: str
    superelements: tuple
    bushings: tuple
    bodies: tuple
    joints: tuple
    node_bodies: dict
    clamps: dict
    welded: dict
    open_springs: tuple
    beta: float

    @property
    def elements(self):
        """Force elements for ``VehicleModel.elements`` (bushings, then the bodies)."""
        return self.bushings + self.superelements


def stiffness_damping_factor(component, bodies, zeta=None):
    """The damping factor beta = 2 zeta / omega_1 [s] (module docstring); ``zeta`` None: the
    component's ``damping_ratio`` (its first value when it is one per mode)."""
    zeta = component.damping_ratio if zeta is None else zeta
    zeta = float(zeta[0] if np.ndim(zeta) else zeta)
    omega_1 = 2 * np.pi * assemble_bodies(component, bodies).frequencies_hz()[0]
    return 2.0 * zeta / omega_1


def _node_name(component, node):
    names = {i: n for n, i in component.node_names.items()}
    return names.get(node, f"node{node}")


def _node_index(component, node):
    if isinstance(node, str):
        if node not in component.node_names:
            raise ModelError(f"{component.source or component.name}: no node '{node}'")
        return component.node_names[node]
    return int(node)


def body_superelement(component, body, parent, reference, beta=0.0, name=None):
    """Superelement of one FlexibleBody ``body`` of ``component`` hanging from vehicle body
    ``parent`` at its boundary node ``reference`` (name or index), every other boundary node an
    end labelled by its node name (module docstring); C = beta K [s]."""
    ref = _node_index(component, reference)
    if ref not in body.boundary:
        raise ModelError(f"{component.source or component.name}: body '{body.name}': node "
                         f"'{_node_name(component, ref)}' is not one of its boundary nodes "
                         f"({', '.join(_node_name(component, n) for n in body.boundary)})")
    xyz = component.node_xyz + component.origin
    position = list(body.boundary).index(ref)
    keep = np.array([i for i in range(body.n) if i // 6 != position or i >= 6 * len(
        body.boundary)], int)
    gamma = np.zeros((body.n, 6))
    gamma[:6 * len(body.boundary)] = rigid_field(xyz[list(body.boundary)])
    m = np.asarray(body.M)[np.ix_(keep, keep)]
    k = np.asarray(body.K)[np.ix_(keep, keep)]
    coupling = np.asarray(body.M)[keep] @ gamma
    ends = tuple((_node_name(component, n), xyz[n].copy()) for n in body.boundary if n != ref)
    return Superelement(name or f"{component.name}_{body.name}", parent, xyz[ref].copy(), m, k,
                        beta * k, ((parent, coupling),), body.n_modes, ends)


def body_elements(component, bodies, hangs, welds=None, open_springs=(), carried=None,
                  zeta=None):
    """The engine elements of a beam component's flexible bodies (module docstring).

    component: a beam :class:`~motoflex_ros.structures.component_model.Component`; bodies: its
    :func:`~motoflex_ros.structures.bodies.reduce_bodies`; hangs: {body name: (vehicle body,
    reference node name)} for every body (a one-node body without elasticity, e.g. an engine
    mount, names the vehicle body its node is on; a clamp node of that kind may be left out
    when ``welds`` names it); welds: {clamp node name: vehicle body} (None: no welds, the
    caller joins ``clamps`` itself); open_springs: (node1, node2) name pairs of springs the
    caller replaces by a vehicle joint (returned as :class:`OpenSpring`, no bushing);
    carried: {(node1, node2): vehicle body P}: that spring's bushing carries P as a fixed tree
    child instead of closing onto it by a cut joint (P, not attached otherwise, is the body
    one of the two nodes hangs from; the bushing hangs from the other node's body), so that P's
    six rigid coordinates are the bushing's (a body held by one spring: a stanchion in its
    fork-bridge joint, a wheel carrier on its pivot); zeta: the damping ratio (None: the
    component's). Returns :class:`BodyElements`.
    """
    source = component.source or component.name
    welds = dict(welds or {})
    _check_names(component, bodies, hangs, welds, source)
    beta = stiffness_damping_factor(component, bodies, zeta)
    build = _Build(component, source, component.node_xyz + component.origin,
                   {n: i for i, b in enumerate(bodies) for n in b.nodes}, {}, beta)
    superelements = _hang_bodies(build, bodies, hangs, welds)
    bushings, closures, left_open = _spring_elements(build, open_springs, carried)
    spherical = _link_joints(build)
    clamps = {_node_name(component, c): build.node_bodies[_node_name(component, c)]
              for c in component.clamp_nodes}
    weld_joints = [Joint(f"{component.name}_weld_{c}", "fixed", welds[c], at, _AXES[0],
                         build.xyz[component.node_names[c]].copy(), cut=True)
                   for c, at in clamps.items() if c in welds and welds[c] != at]
    parts = [chain_parts(e) for e in bushings + superelements]
    return BodyElements(component.name, tuple(superelements), tuple(bushings),
                        tuple(b for p in parts for b in p[0]),
                        tuple(j for p in parts for j in p[1]) + tuple(closures)
                        + tuple(spherical) + tuple(weld_joints),
                        build.node_bodies, clamps, welds, tuple(left_open), beta)


@dataclass
class _Build:
    """What the steps of :func:`body_elements` share: the component, its name for messages,
    node positions [m] (vehicle frame), {node index: body index}, {node name: engine body}
    (filled by :func:`_hang_bodies`) and the damping factor beta [s]."""

    component: object
    source: str
    xyz: np.ndarray
    body_of: dict
    node_bodies: dict
    beta: float


def _check_names(component, bodies, hangs, welds, source):
    """ModelError when ``welds`` names a node that is no clamp or ``hangs`` a body that the
    component does not have."""
    clamp_names = {_node_name(component, c) for c in component.clamp_nodes}
    unknown = sorted(set(welds) - clamp_names)
    if unknown:
        raise ModelError(f"{source}: welds name {', '.join(unknown)}, which are not clamps "
                         f"(clamps: {', '.join(sorted(clamp_names))})")
    extra = sorted(set(hangs) - {b.name for b in bodies})
    if extra:
        raise ModelError(f"{source}: hangs name bodies {', '.join(extra)} the component does "
                         f"not have (bodies: {', '.join(b.name for b in bodies)})")


def _hang_bodies(build, bodies, hangs, welds):
    """The superelement of every elastic body, hung where ``hangs`` (or, for a rigid one-node
    body, ``welds``) says; fills ``build.node_bodies``."""
    component, source = build.component, build.source
    superelements = []
    for body in bodies:
        elastic = body.n_modes > 0 or np.any(body.K)
        if body.name in hangs:
            parent, reference = hangs[body.name]
        elif not elastic and _node_name(component, body.nodes[0]) in welds:
            parent, reference = welds[_node_name(component, body.nodes[0])], body.nodes[0]
        else:
            raise ModelError(f"{source}: body '{body.name}' has no entry in hangs (the vehicle "
                             "body it hangs from and its reference node)")
        if not elastic:
            if len(body.nodes) != 1:
                raise ModelError(f"{source}: body '{body.name}' has no stiffness")
            build.node_bodies[_node_name(component, body.nodes[0])] = parent
            continue
        se = body_superelement(component, body, parent, reference, build.beta)
        superelements.append(se)
        build.node_bodies[_node_name(component, _node_index(component, reference))] = parent
        for label in se.end_labels:
            build.node_bodies[label] = end_body(se, label)
    return superelements


def _spring_elements(build, open_springs, carried):
    """(bushings, their closing or carrying joints, OpenSprings) of the springs that join two
    bodies (module docstring; ``open_springs`` and ``carried`` as in :func:`body_elements`)."""
    component, source, node_bodies = build.component, build.source, build.node_bodies
    wanted_open = {frozenset(pair) for pair in open_springs}
    carriers = {frozenset(pair): body for pair, body in (carried or {}).items()}
    bushings, closures, left_open = [], [], []
    for n1, n2, block in component.structure.springs:
        if build.body_of[n1] == build.body_of[n2]:
            continue
        a, b = _node_name(component, n1), _node_name(component, n2)
        gap = float(np.linalg.norm(build.xyz[n1] - build.xyz[n2]))
        if gap > COINCIDENT_TOLERANCE:
            raise ModelError(f"{source}: the spring {a}-{b} joins nodes {gap:.3g} m apart; a "
                             "bushing joins coincident nodes")
        if frozenset((a, b)) in wanted_open:
            wanted_open.discard(frozenset((a, b)))
            left_open.append(OpenSpring(a, b, node_bodies[a], node_bodies[b],
                                        build.xyz[n1].copy(), np.array(block)))
            continue
        carry = carriers.pop(frozenset((a, b)), None)
        built = _bushing(build, a, b, n1, block, carry)
        if built is not None:
            bushings.append(built[0])
            closures.append(built[1])
    for what, left in (("open_springs", wanted_open), ("carried", carriers)):
        if left:
            pairs = ", ".join("-".join(sorted(p)) for p in left)
            raise ModelError(f"{source}: {what} {pairs}: no spring joins two bodies there")
    return bushings, closures, left_open


def _bushing(build, a, b, n1, block, carry):
    """(bushing, joint) of the spring between nodes ``a`` and ``b`` (names) at node index
    ``n1``: closed onto b's body by a fixed cut joint, or carrying the body ``carry``; None
    when both ends are on one rigid vehicle body (the spring never deforms)."""
    node_bodies = build.node_bodies
    if carry is not None and carry not in (node_bodies[a], node_bodies[b]):
        raise ModelError(f"{build.source}: carried: the spring {a}-{b} joins bodies on "
                         f"'{node_bodies[a]}' and '{node_bodies[b]}', not '{carry}'")
    if carry is not None and node_bodies[a] == carry:
        a, b = b, a     # hang from the other node's body: x = u_b - u_a, same energy
    if node_bodies[a] == node_bodies[b]:
        return None
    element = bushing(f"{build.component.name}_{a}_{b}", node_bodies[a], build.xyz[n1], block,
                      build.beta * np.asarray(block))
    joint = Joint(f"{element.name}_close" if carry is None else f"{element.name}_carry",
                  "fixed", end_body(element), node_bodies[b], _AXES[0], build.xyz[n1].copy(),
                  cut=carry is None)
    return element, joint


def _link_joints(build):
    """Spherical cut joints of the rigid links (translations) between two bodies."""
    component, node_bodies = build.component, build.node_bodies
    spherical = []
    for master, slave, dofs in component.structure.links:
        if build.body_of[master] == build.body_of[slave]:
            continue
        if len(dofs) != 3:
            raise ModelError(f"{build.source}: a rigid link joining two bodies must link the "
                             "translations only")
        a, b = _node_name(component, master), _node_name(component, slave)
        if node_bodies[a] != node_bodies[b]:
            spherical.append(Joint(f"{component.name}_link_{a}_{b}", "spherical",
                                   node_bodies[a], node_bodies[b], _AXES[0],
                                   build.xyz[slave].copy(), axis2=_AXES[1], cut=True))
    return spherical


def add_to(model, built):
    """``model`` (a VehicleModel) with the :class:`BodyElements` ``built`` added: its bodies,
    joints (after the model's own, so that the model's joints stay the dependent ones of its
    loops) and force elements."""
    return replace(model, bodies=model.bodies + built.bodies,
                   joints=model.joints + built.joints,
                   elements=model.elements + built.elements)


def _free_chain(name, parent, point):
    """Massless bodies and the six joints (prismatic x, y, z, revolute x, y, z through
    ``point``) that let body ``name`` move freely relative to ``parent``."""
    bodies, joints = [], []
    for i in range(6):
        child = name if i == 5 else f"{name}_free{i}"
        if i < 5:
            bodies.append(Body(child, 0.0, np.asarray(point, float), np.zeros((3, 3))))
        joints.append(Joint(f"{name}_{('x', 'y', 'z', 'rx', 'ry', 'rz')[i]}",
                            "prismatic" if i < 3 else "revolute", parent, child, _AXES[i % 3],
                            np.asarray(point, float)))
        parent = child
    return bodies, joints


def bench_model(component, bodies=None, zeta=None, carry=False):
    """The component on the bench in the engine: a fixed-base VehicleModel (gravity 0) with
    its flexible bodies (:func:`body_elements`), its clamps welded to the body 'ground'.

    A body that holds a clamp hangs from the ground at its first clamp node. Every other body
    hangs from its own rigid body '<body>_rigid' (mass, centre of mass and inertia of
    :func:`~motoflex_ros.structures.bodies.body_mass_properties`), which carries its rigid
    motion and mass: ``carry`` False: the rigid body on six joints from the ground, the body
    hanging at its first boundary node; ``carry`` True: where a spring joins the body to one
    already placed (clamped bodies first, then outwards), the rigid body carried by that
    spring's bushing (``carried`` of :func:`body_elements`) and the body hanging at the
    spring's node; six joints from the ground only for a body no spring reaches.
    ``bodies``: :func:`~motoflex_ros.structures.bodies.reduce_bodies` of the component
    (None: reduced here with the defaults). Returns (VehicleModel, BodyElements).
    """
    bodies = reduce_bodies(component) if bodies is None else bodies
    rigid_bodies = [Body("ground", 0.0, np.zeros(3), np.zeros((3, 3)))]
    hangs = _clamped_hangs(component, bodies)
    carried = _carried_hangs(component, bodies, hangs, rigid_bodies) if carry else {}
    rigid_joints = _free_hangs(component, bodies, hangs, rigid_bodies)
    welds = {_node_name(component, c): "ground" for c in component.clamp_nodes}
    built = body_elements(component, bodies, hangs, welds, carried=carried, zeta=zeta)
    model = VehicleModel(f"{component.name}_bench", f"{component.source or component.name} "
                         "(bench, flexible bodies)", 0.0, "ground", tuple(rigid_bodies),
                         tuple(rigid_joints), (), base="fixed")
    return add_to(model, built), built


def _clamped_hangs(component, bodies):
    """{body: ("ground", its first clamp node)} of the bodies that hold a clamp."""
    clamps = set(component.clamp_nodes)
    hangs = {}
    for body in bodies:
        held = [n for n in body.boundary if n in clamps]
        if held:
            hangs[body.name] = ("ground", _node_name(component, held[0]))
    return hangs


def _carried_hangs(component, bodies, hangs, rigid_bodies):
    """Outwards from the bodies placed in ``hangs``: each body a spring joins to a placed one
    hangs from its rigid body '<body>_rigid' at the spring's node, carried by that spring's
    bushing. Adds to ``hangs`` and ``rigid_bodies``; returns ``carried`` of
    :func:`body_elements`."""
    body_of = {n: b.name for b in bodies for n in b.nodes}
    springs = [(n1, n2) for n1, n2, _ in component.structure.springs
               if body_of[n1] != body_of[n2]]
    carried = {}
    while True:
        step = [(a, b) for n1, n2 in springs for a, b in ((n1, n2), (n2, n1))
                if body_of[a] in hangs and body_of[b] not in hangs]
        if not step:
            return carried
        a, b = step[0]
        body = next(x for x in bodies if x.name == body_of[b])
        name = f"{body.name}_rigid"
        hangs[body.name] = (name, _node_name(component, b))
        carried[(_node_name(component, a), _node_name(component, b))] = name
        mass, com, inertia = body_mass_properties(component.structure, body.nodes)
        rigid_bodies.append(Body(name, mass, com + component.origin, inertia))


def _free_hangs(component, bodies, hangs, rigid_bodies):
    """Every body not yet in ``hangs`` on its rigid body '<body>_rigid', free on six joints
    from the ground, hanging at its first boundary node. Adds to ``hangs`` and
    ``rigid_bodies``; returns the joints."""
    xyz = component.node_xyz + component.origin
    rigid_joints = []
    for body in bodies:
        if body.name in hangs:
            continue
        ref = body.boundary[0]
        mass, com, inertia = body_mass_properties(component.structure, body.nodes)
        name = f"{body.name}_rigid"
        chain_bodies, chain_joints = _free_chain(name, "ground", xyz[ref])
        rigid_bodies += chain_bodies + [Body(name, mass, com + component.origin, inertia)]
        rigid_joints += chain_joints
        hangs[body.name] = (name, _node_name(component, ref))
    return rigid_joints


def point_jacobian(system, body, point):
    """(6, n_indep) map from the independent coordinates of ``system`` (a VehicleSystem) to the
    small motion (u [m], theta [rad]) of the material point of engine body ``body`` at
    ``point`` [m] (reference configuration), including the coordinates the loops make
    dependent: J S with S = dq/dq_indep (complex step through the loop closure)."""
    from motoflex_ros.vehicle.dynamics import positions
    from motoflex_ros.vehicle.kinematics import frame_states
    n = len(system.tree.coordinates)
    nq = len(system.indep_pos)
    f = frame_states(system.tree, np.zeros(n), np.zeros(n))[system.tree.body_frames[body]]
    jac = np.vstack([f.point_velocity_jacobian(np.asarray(point, float)), f.Jw])
    step = 1e-30
    S = np.zeros((n, nq))
    for j in range(nq):
        x = np.zeros(system.n_states, complex)
        x[j] = 1j * step
        S[:, j] = positions(system, x, newton_steps=1).imag / step
    return jac @ S
