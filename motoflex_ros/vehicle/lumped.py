"""Lumped stiffness motorcycles: the paper's variants as edits of one vehicle description.

Passigato et al. 2023, Sect. 4.1 (model), end of Sect. 5.1 (inertia distribution) and 5.2
(variants). Every variant is the rigid :class:`~motoflex_ros.vehicle.model.VehicleModel` with
extra bodies and revolute joints put in, never a separate engine:

- frame: split in two. The body carrying the steering head (``frame_head``) hangs from the rest
  of the frame by the flexible joint; the steering joint now hangs from ``frame_head``.
- front assembly and swingarm: a (massless) body between the wheel carrier and the wheel,
  attached to the carrier by the flexible joint; the wheel spins on it.

Variants (``VARIANTS``):

===================  ===========================================  ===========================
variant              joint axis and stiffness                     inertia on the new body
===================  ===========================================  ===========================
rigid                none                                          -
state_of_the_art     literature axes (Sect. 5.2.1-5.2.3), k from   front: lower fork moved
                     a static moment about that axis on the FE     (c.o.g. unchanged)
                     model
static               static test: l, beta, k (eqs. 1-8)            front: lower fork moved
torsion, bending     harmonic test at the first torsion/bending    J (eq. 10) about the axis,
                     frequency; c from eq. (11)                    taken from the donor
decomposed           two joints in series: torsion axis with k_t   as static
                     and bending axis with k_b (eq. 12)
principal            joints in series: the principal hinges of     as static
                     the bench's 3 x 3 end compliance (beyond the
                     paper, identify/principal.py)
fitted, road_load,   one joint as static, its l, beta, k found     as static
vehicle_load         otherwise (``HINGE_VARIANTS``: beyond the
                     paper, :mod:`motoflex_ros.study.fitted` and
                     the bench tests loaded as in the vehicle)
===================  ===========================================  ===========================

Static models get c = gamma k with gamma = 0.001 s (Sect. 5.2.4). The identified inertia J
[kg m^2] is put on the new body as the rank-one tensor J a a^T about the joint axis a (the only
rotation the joint lets it make relative to its parent) and the same tensor is taken from the
donor body (frame, lower fork, wheel carrier), so the motorcycle's total mass, centre of mass and
inertia stay exactly those of the rigid motorcycle. A tensor with zero mass is the same about
any point, which is what makes the bookkeeping exact.

Axes from identification are in the component frame (clamp O at ``placement.origin`` in the
vehicle frame, axes parallel to the vehicle's): the joint lies at the signed distance l along
O-q0 and makes the angle beta with O-q0 in the x-z plane (eqs. 5-6).
"""
from dataclasses import dataclass, replace

import numpy as np

from motoflex_ros.config import MOTORCYCLE_COMPONENTS
from motoflex_ros.errors import ConfigError, ModelError
from motoflex_ros.inertia import composite_inertia
from motoflex_ros.vehicle.dynamics import build_system, dependent_speeds
from motoflex_ros.vehicle.kinematics import frame_states
from motoflex_ros.vehicle.model import Body, Joint

__all__ = ["VARIANTS", "COMPONENTS", "FlexJoint", "ComponentSite", "site_of", "axis_in_vehicle",
           "state_of_the_art_axis", "check_site", "reattach", "lumped_vehicle", "mass_properties",
           "MOUNTS", "SUPERELEMENT_PARENT", "SUPERELEMENT_FOLLOWS", "NEW_BODY",
           "HINGE_VARIANTS", "CARRIED", "carried_inertia"]

VARIANTS = ("rigid", "state_of_the_art", "static", "torsion", "bending", "decomposed",
            "principal")
HINGE_VARIANTS = ("fitted", "road_load", "vehicle_load")
"""Single hinges as the static model's (c = gamma k, same inertia distribution) whose l, beta
and k come from elsewhere than the paper's static test: fitted to the flexible motorcycle,
or identified from a bench test loaded as the road (or the vehicle) loads the component."""
COMPONENTS = MOTORCYCLE_COMPONENTS

MOUNTS = {
    # component: (donor body, what hangs from the new body: ('joint', role) or ('wheel', name))
    "frame": ("frame", ("joint", "steer")),
    "front_assembly": ("lower_fork", ("wheel", "front")),
    "swingarm": ("wheel_carrier", ("wheel", "rear")),
}
NEW_BODY = {"frame": "frame_head", "front_assembly": "front_flex", "swingarm": "rear_flex"}
SUPERELEMENT_PARENT = {"frame": "frame", "front_assembly": "lower_fork", "swingarm": "swingarm"}
"""Body each component's superelement hangs its elastic coordinates from in the flexible
motorcycle (frame: the rear frame with the engine mounts; swingarm: the main arm, locked on its
pivot; front assembly: the steered lower fork, which carries the wheel)."""
SUPERELEMENT_FOLLOWS = {
    "front_assembly": {"upper_fork": ("fork_bridge", "stanchion_top_left",
                                      "stanchion_top_right"),
                       "telelever_arm": ("arm_pivot",)},
    "swingarm": {"torque_strut": ("strut_frame",), "wheel_carrier": ("carrier_pivot",)},
}
"""Which vehicle body each of a component's bodies (paper Table A.1) moves rigidly with, by a
node of that body; the bodies not named follow SUPERELEMENT_PARENT. The front assembly's arm
is on its pivot in the frame and does not steer; its bridge and stanchions hang from the head
joint (docs/boundary-conditions.md)."""
CARRIED = {
    # component: (bodies, wheels, passes moments): what the loaded end carries
    "frame": (("upper_fork", "lower_fork"), ("front",), False),
    "front_assembly": (("lower_fork",), ("front",), True),
    "swingarm": ((), ("rear",), True),
}
"""What hangs from each component's loaded end, for the metric of its principal hinges
(:mod:`motoflex_ros.identify.principal`): the front assembly carries the lower fork (its wheel
carrier) and the front wheel; the swingarm the rear wheel (the wheel carrier is part of the
component); the frame's steering head carries the front, but through the Telelever's spherical
head joint, which passes no moment: only its mass at the head counts."""
TOLERANCE = 1e-3
"""How far [m] a component's interface point may lie from the vehicle's joint point."""


@dataclass(frozen=True)
class FlexJoint:
    """A lumped flexibility: revolute joint through ``point`` [m] along unit ``axis`` (vehicle
    frame), stiffness k [N m/rad], damping c [N m s/rad], inertia J [kg m^2] about the axis."""

    name: str
    point: np.ndarray
    axis: np.ndarray
    k: float
    c: float
    J: float = 0.0


@dataclass(frozen=True)
class ComponentSite:
    """Where a component sits in the vehicle: origin O [m] (vehicle frame), q0 [m] (component
    frame) and named points [m] (component frame)."""

    name: str
    origin: np.ndarray
    q0: np.ndarray
    points: dict


def site_of(component):
    """ComponentSite of a structures Component (placement origin, loaded end, named nodes)."""
    points = {n: component.node_xyz[i] for n, i in component.node_names.items()}
    return ComponentSite(component.name, np.asarray(component.origin, float),
                         np.asarray(component.q0, float), points)


def axis_in_vehicle(site, l, beta):
    """Joint point [m] and unit axis in the vehicle frame from l [m] and beta [rad] (eqs. 5-6).

    The joint lies at l along the unit vector e0 = (x_q0, z_q0)/L; the axis direction is at
    theta_0 + beta in the x-z plane, theta_0 = atan2(z_q0, x_q0) (eq. 6: beta = theta_j -
    theta_0).
    """
    q0 = site.q0
    theta0 = np.arctan2(q0[2], q0[0])
    e0 = np.array([np.cos(theta0), 0.0, np.sin(theta0)])
    direction = np.array([np.cos(theta0 + beta), 0.0, np.sin(theta0 + beta)])
    return site.origin + l * e0, direction


def _perpendicular_in_plane(direction):
    """Unit vector in the x-z plane perpendicular to ``direction`` (e.g. to the fork axis)."""
    d = np.asarray(direction, float)
    return np.array([d[2], 0.0, -d[0]]) / np.hypot(d[0], d[2])


def state_of_the_art_axis(component, site, steer_axis):
    """Point [m] and axis of the literature's joint for a component (Sect. 5.2.1-5.2.3).

    frame: torsion at the steering head, axis perpendicular to the fork (steering) axis [5];
    front assembly: bending at the spherical joint of the longitudinal arm, axis perpendicular
    to the fork axis [11]; swingarm: axis parallel to x at the wheel centre [33].
    """
    if component == "frame":
        return site.origin + site.q0, _perpendicular_in_plane(steer_axis)
    if component == "front_assembly":
        if "lower_joint_fork" not in site.points:
            raise ModelError(f"front assembly '{site.name}' names no node 'lower_joint_fork' "
                             "(the spherical joint of the longitudinal arm)")
        return site.origin + site.points["lower_joint_fork"], _perpendicular_in_plane(steer_axis)
    return site.origin + site.q0, np.array([1.0, 0.0, 0.0])


def mass_properties(model):
    """Total mass [kg], centre of mass [m] and inertia tensor about it [kg m^2] of a vehicle.

    Bodies and wheels (a wheel: diametral inertia about the axes normal to its spin axis,
    spin inertia about it), reference configuration.
    """
    items = [(b.mass, b.com, b.inertia) for b in model.bodies]
    items += [(w.mass, w.centre, w.inertia) for w in model.wheels]
    return composite_inertia(items)


def carried_inertia(model, component):
    """(mass [kg], centre of mass [m] (vehicle frame), inertia about it [kg m^2], passes
    moments, names) of what ``component``'s loaded end carries in ``model`` (:data:`CARRIED`),
    in the reference configuration."""
    body_names, wheel_names, passes = CARRIED[component]
    bodies = {b.name: b for b in model.bodies}
    items = [(b.mass, b.com, b.inertia) for b in (_body(bodies, n, model) for n in body_names)]
    items += [(w.mass, w.centre, w.inertia) for w in (_wheel(model, n) for n in wheel_names)]
    mass, com, inertia = composite_inertia(items)
    return mass, com, inertia, passes, body_names + wheel_names


def _distance_to_line(point, line_point, direction):
    d = np.asarray(direction, float) / np.linalg.norm(direction)
    r = np.asarray(point, float) - np.asarray(line_point, float)
    return float(np.linalg.norm(r - (r @ d) * d))


def check_site(model, component, site):
    """Raise ModelError unless the component's loaded end meets the vehicle within 1 mm.

    frame: the steering head (q0) on the steering axis; front assembly and swingarm: q0 at the
    front and rear wheel centres.
    """
    q0 = site.origin + site.q0
    kind, name = MOUNTS[component][1]
    if kind == "joint":
        steer = _joint(model, model.roles.get(name, name))
        gap = _distance_to_line(q0, steer.point, steer.axis)
        what = f"the {name} axis"
    else:
        gap = float(np.linalg.norm(q0 - _wheel(model, name).centre))
        what = f"the {name} wheel centre"
    if gap > TOLERANCE:
        raise ModelError(f"component '{component}' ({site.name}): its loaded end "
                         f"{np.round(q0, 4).tolist()} m is {gap * 1e3:.1f} mm from {what} of "
                         f"vehicle '{model.name}' (allowed 1 mm); check placement.origin")


def _joint(model, name):
    hits = [j for j in model.joints if j.name == name]
    if not hits:
        raise ModelError(f"vehicle '{model.name}' has no joint '{name}'")
    return hits[0]


def _wheel(model, name):
    hits = [w for w in model.wheels if w.name == name]
    if not hits:
        raise ModelError(f"vehicle '{model.name}' has no wheel '{name}'")
    return hits[0]


def _body(bodies, name, model):
    if name not in bodies:
        raise ModelError(f"vehicle '{model.name}' has no body '{name}'")
    return bodies[name]


def _rigid_cluster(model, name):
    """Names of the bodies that move as one with body ``name``: welded to it by fixed joints,
    or held to it by a frozen mechanism (locked coordinates closing a loop, e.g. the wheel
    carrier of the locked Paralever). Found from the kinematics: a body belongs to the cluster
    when its frame has the twist of ``name``'s frame for every independent speed."""
    system = build_system(model)
    tree = system.tree
    zero = np.zeros(len(tree.coordinates))
    cluster = {b.name for b in model.bodies}
    for k in system.indep_speed:
        known = zero.copy()
        known[k] = 1.0
        frames = frame_states(tree, zero, dependent_speeds(system, zero, known))
        twists = {b: np.concatenate([frames[tree.body_frames[b]].w,
                                     frames[tree.body_frames[b]].v0]) for b in cluster | {name}}
        cluster = {b for b in cluster if np.allclose(twists[b], twists[name], atol=1e-9)}
    return cluster


def _take_inertia(donor, tensor, bodies, model):
    """The donor body with ``tensor`` [kg m^2] removed.

    The identified J is a modal inertia about the hinge; it can exceed what the donor has about
    its own centre of mass (the donor's mass swings about the hinge too). What must stay
    physical is the rigid cluster the donor is welded into (e.g. lower fork + upper fork):
    its inertia about its centre of mass must stay positive definite.
    """
    rest = replace(donor, inertia=donor.inertia - tensor)
    members = [rest if n == donor.name else bodies[n]
               for n in _rigid_cluster(model, donor.name)]
    _, _, total = composite_inertia((b.mass, b.com, b.inertia) for b in members)
    if np.linalg.eigvalsh(total)[0] <= 0.0:
        names = ", ".join(sorted(b.name for b in members))
        raise ModelError(f"vehicle '{model.name}': the identified inertia "
                         f"{np.trace(tensor):.4g} kg m^2 exceeds what the rigid bodies {names} "
                         "have about that axis; it cannot be moved to the lumped joint")
    return rest


def _new_body_inertia(component, variant, joints, bodies, model):
    """(new body, updated donor) following the paper's inertia distribution (Sect. 5.1, 5.2)."""
    donor_name = MOUNTS[component][0]
    donor = _body(bodies, donor_name, model)
    last = joints[-1]
    if variant in ("torsion", "bending"):
        tensor = last.J * np.outer(last.axis, last.axis)
        return (Body(NEW_BODY[component], 0.0, last.point.copy(), tensor),
                _take_inertia(donor, tensor, bodies, model))
    if component == "front_assembly":
        # the lower fork moves to the massless body, centre of gravity unchanged (Sect. 5.2.2)
        return (replace(donor, name=NEW_BODY[component]),
                Body(donor.name, 0.0, donor.com.copy(), np.zeros((3, 3))))
    return Body(NEW_BODY[component], 0.0, last.point.copy(), np.zeros((3, 3))), donor


def _insert(model, component, variant, joints, bodies, joint_list, wheels):
    """Put the chain donor -> joints -> new body into the model's parts lists (in place)."""
    new_body, donor = _new_body_inertia(component, variant, joints, bodies, model)
    bodies[donor.name] = donor
    parent = MOUNTS[component][0]
    for i, fj in enumerate(joints):
        child = new_body.name if i == len(joints) - 1 else f"{component}_mid{i}"
        if child != new_body.name:
            bodies[child] = Body(child, 0.0, fj.point.copy(), np.zeros((3, 3)))
        joint_list.append(Joint(fj.name, "revolute", parent, child, fj.axis, fj.point,
                                fj.k, fj.c))
        parent = child
    bodies[new_body.name] = new_body
    reattach(model, component, joint_list, wheels, new_body.name)


def reattach(model, component, joint_list, wheels, new_parent):
    """Hang what the component carries (steering joint or wheel) from body ``new_parent``.

    Edits ``joint_list`` or ``wheels`` (lists of the model's joints and wheels) in place.
    """
    kind, name = MOUNTS[component][1]
    if kind == "joint":
        role = model.roles.get(name, name)
        idx = next(i for i, j in enumerate(joint_list) if j.name == role)
        joint_list[idx] = replace(joint_list[idx], parent=new_parent)
    else:
        idx = next(i for i, w in enumerate(wheels) if w.name == name)
        wheels[idx] = replace(wheels[idx], carrier=new_parent)


def lumped_vehicle(model, variant, joints_by_component):
    """The rigid ``model`` with the lumped flexibilities of ``joints_by_component`` put in.

    ``joints_by_component`` maps a component name (frame, front_assembly, swingarm) to its
    FlexJoint tuple (:func:`flex_joints`). ``variant`` decides the inertia distribution.
    Returns a new VehicleModel; total mass, centre of mass and inertia are unchanged.
    """
    if variant not in VARIANTS + HINGE_VARIANTS:
        raise ConfigError("--flex", "variant", f"'{variant}' is not one of: "
                                               f"{', '.join(VARIANTS + HINGE_VARIANTS)}")
    if variant == "rigid" or not joints_by_component:
        return model
    bodies = {b.name: b for b in model.bodies}
    joint_list = list(model.joints)
    wheels = list(model.wheels)
    for component, joints in joints_by_component.items():
        if component not in MOUNTS:
            raise ConfigError("--component", component, "unknown component (allowed: "
                                                         f"{', '.join(COMPONENTS)})")
        _insert(model, component, variant, joints, bodies, joint_list, wheels)
    flex = {**model.flex, "variant": variant, "components": tuple(joints_by_component)}
    return replace(model, name=f"{model.name}+{variant}", bodies=tuple(bodies.values()),
                   joints=tuple(joint_list), wheels=tuple(wheels), flex=flex)
