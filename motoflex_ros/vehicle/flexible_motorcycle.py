"""The flexible motorcycle of the paper: per-body superelements joined by the vehicle's joints.

Passigato et al. 2023, Sect. 4.1 and Appendix (Table A.1): the ground truth is a multibody
model whose flexible bodies (frame; fork bridge, two stanchions, lower fork, longitudinal arm;
lower link, upper link, wheel carrier) are each reduced by Craig-Bampton with their joint
points as interface nodes, and joined in the vehicle by joints. Here every beam component's
bodies (:func:`~motoflex_ros.structures.bodies.reduce_bodies`) enter the touring motorcycle
through :func:`~motoflex_ros.vehicle.flexible_bodies.body_elements`:

- each flexible body hangs from the vehicle body that carries its rigid motion and mass, at a
  reference node; its other joint points are ends that the joints use;
- the component's springs are its compliant joints (engine mounts, the joint links of the
  stanchions in the fork bridge, the slider bushings, the lower ball joint, the wheel-carrier
  bearing): bushings at the same points, in place of the rigid vehicle's joints there
  (``removed``), and its translation-only links are spherical joints (the torque strut's ball);
- where the component is clamped on the bench, the vehicle's own joint holds it: the steering
  head (the spherical joint ``steer``, free about the steering axis where the bench locks it:
  the head spring is opened and the vehicle's joint takes its place), the locked pivots of the
  longitudinal arm and of the Paralever (``locked``: frozen suspension travel, on the bench the
  clamps), the engine mounts (welded to the rigid engine), the torque strut's universal joint
  on the frame.

A body that only springs hold (the main frame on its engine mounts, a stanchion in its joint
link, the lower fork in its ball joint and bushings, the wheel carrier in its bearing) is
carried by one of those springs (``carried``): its rigid coordinates are that bushing's. Its
vehicle body carries its rigid mass: the main frame and the stanchions are new bodies with the
FE bodies' mass, centre of mass and inertia
(:func:`~motoflex_ros.structures.bodies.body_mass_properties`), taken out of the rigid
vehicle's ``frame`` and ``upper_fork`` (``split``), so the motorcycle's total mass, centre of
mass and inertia stay the rigid motorcycle's (test_flexible_motorcycle); the lower fork and the
Paralever's bodies already are the FE bodies (docs/boundary-conditions.md).

Components without a beam model (a mesh or a pre-reduced superelement, ``--use``) enter as
one clamped superelement, as the bench reduced them
(:func:`~motoflex_ros.vehicle.variants.flexible_vehicle`).
"""
from dataclasses import dataclass, field, replace

import numpy as np

from motoflex_ros.errors import ModelError
from motoflex_ros.inertia import composite_inertia
from motoflex_ros.structures.bodies import body_mass_properties, reduce_bodies
from motoflex_ros.vehicle.flexible_bodies import body_elements
from motoflex_ros.vehicle.lumped import SUPERELEMENT_FOLLOWS, SUPERELEMENT_PARENT
from motoflex_ros.vehicle.model import Body
from motoflex_ros.vehicle.superelement import chain_parts, end_body, superelement_of

__all__ = ["PerBody", "PER_BODY", "per_body_vehicle", "has_bodies"]


@dataclass(frozen=True)
class PerBody:
    """How one component's flexible bodies enter the touring motorcycle.

    hangs: {FE body: (vehicle body, reference node)}; carried: {(node1, node2): vehicle body}
    the spring whose bushing carries that body; welds: {clamp node: vehicle body} ('head': the
    body that carries the steering head, the frame's end there when the frame is flexible);
    open_springs: springs the vehicle's joint replaces; removed: rigid-vehicle joints the
    component's springs and links replace; locked: joints whose coordinate is frozen (the bench
    clamp); split: {new vehicle body: (vehicle body it comes out of, FE bodies)}; carries:
    {node: what hangs from it: ('joint', role) or ('wheel', name)}.
    """

    hangs: dict
    carried: dict = field(default_factory=dict)
    welds: dict = field(default_factory=dict)
    open_springs: tuple = ()
    removed: tuple = ()
    locked: tuple = ()
    split: dict = field(default_factory=dict)
    carries: dict = field(default_factory=dict)


_MOUNTS = ("rear_left", "rear_right", "front_left", "front_right")

PER_BODY = {
    "frame": PerBody(
        hangs={"frame": ("main_frame", "frame_mount_rear_left")},
        carried={("engine_mount_rear_left", "frame_mount_rear_left"): "main_frame"},
        welds={f"engine_mount_{m}": "frame" for m in _MOUNTS},
        split={"main_frame": ("frame", ("frame",))},
        carries={"steering_head": ("joint", "steer")}),
    "front_assembly": PerBody(
        hangs={"fork_bridge": ("upper_fork", "fork_bridge"),
               "stanchion_left": ("stanchion_left", "stanchion_top_left"),
               "stanchion_right": ("stanchion_right", "stanchion_top_right"),
               "lower_fork": ("lower_fork", "lower_joint_fork"),
               "longitudinal_arm": ("telelever_arm", "arm_pivot")},
        carried={("fork_top_left", "stanchion_top_left"): "stanchion_left",
                 ("fork_top_right", "stanchion_top_right"): "stanchion_right",
                 ("lower_joint_arm", "lower_joint_fork"): "lower_fork"},
        welds={"steering_head": "head", "arm_pivot_left": "frame", "arm_pivot_right": "frame"},
        open_springs=(("steering_head", "fork_bridge"),),
        removed=("stanchion_slide", "telelever_ball"),
        locked=("telelever_arm_pivot",),
        split={"stanchion_left": ("upper_fork", ("stanchion_left",)),
               "stanchion_right": ("upper_fork", ("stanchion_right",))},
        carries={"front_axle": ("wheel", "front")}),
    "swingarm": PerBody(
        hangs={"lower_link": ("swingarm", "swingarm_pivot"),
               "upper_link": ("torque_strut", "strut_frame"),
               "wheel_carrier": ("wheel_carrier", "carrier_pivot")},
        carried={("arm_rear", "carrier_pivot"): "wheel_carrier"},
        welds={"pivot_left": "frame", "pivot_right": "frame"},
        removed=("wheel_carrier_pivot", "torque_strut_ball"),
        locked=("swingarm_pivot",),
        carries={"rear_axle": ("wheel", "rear")}),
}
"""The touring motorcycle's per-body map (config/vehicles/touring.yaml, config/components/;
docs/boundary-conditions.md)."""


def has_bodies(component):
    """True when ``component`` is a beam model whose bodies can be taken apart (a mesh or a
    pre-reduced superelement is one reduced model)."""
    return getattr(component, "structure", None) is not None and bool(
        getattr(component.structure, "elements", None))


def _take_out(body, fe, component, names, source):
    """``body`` (a vehicle Body) less the FE bodies ``names`` of ``component`` (mass, centre of
    mass and inertia), and the new Body that carries them."""
    nodes = [n for b in fe if b.name in names for n in b.nodes]
    mass, com, inertia = body_mass_properties(component.structure, nodes)
    com = com + component.origin
    rest = composite_inertia([(body.mass, body.com, body.inertia), (-mass, com, -inertia)])
    if rest[0] <= 0.0 or np.linalg.eigvalsh(rest[2])[0] <= 0.0:
        raise ModelError(f"{source}: the FE bodies {', '.join(names)} ({mass:.4g} kg) do not "
                         f"fit inside the vehicle body '{body.name}' ({body.mass:.4g} kg)")
    return Body(body.name, rest[0], rest[1], rest[2]), (mass, com, inertia)


def per_body_vehicle(vehicle, components, names, table=None):
    """The rigid ``vehicle`` with the components ``names`` as per-body superelements joined by
    its joints (module docstring); ``components``: {name: beam Component}; ``table``: the
    per-body map (default :data:`PER_BODY`). Returns a VehicleModel."""
    table = PER_BODY if table is None else table
    bodies = {b.name: b for b in vehicle.bodies}
    joints = {j.name: j for j in vehicle.joints}
    wheels = list(vehicle.wheels)
    extra_bodies, extra_joints, elements = [], [], []
    head = "frame"
    for name in [n for n in ("frame", "front_assembly", "swingarm") if n in names]:
        spec, component = table[name], components[name]
        if not has_bodies(component):
            se = superelement_of(component, SUPERELEMENT_PARENT[name],
                                 follows=SUPERELEMENT_FOLLOWS.get(name))
            parts = chain_parts(se)
            extra_bodies += parts[0]
            extra_joints += parts[1]
            elements.append(se)
            node_bodies = {node: end_body(se) for node in spec.carries}
        else:
            node_bodies = _add_bodies(vehicle, name, spec, component, head, bodies, joints,
                                      (extra_bodies, extra_joints, elements))
        for node, (kind, what) in spec.carries.items():
            carrier = node_bodies[node]
            if kind == "joint":
                role = vehicle.roles.get(what, what)
                joints[role] = replace(joints[role], parent=carrier)
                head = carrier
            else:
                index = next(i for i, w in enumerate(wheels) if w.name == what)
                wheels[index] = replace(wheels[index], carrier=carrier)
    flex = {**vehicle.flex, "variant": "flexible_bodies", "components": tuple(names)}
    return replace(vehicle, name=f"{vehicle.name}+flexible_bodies",
                   bodies=tuple(bodies.values()) + tuple(extra_bodies),
                   joints=tuple(joints.values()) + tuple(extra_joints),
                   wheels=tuple(wheels), elements=vehicle.elements + tuple(elements), flex=flex)


def _add_bodies(vehicle, name, spec, component, head, bodies, joints, out):
    """Put one beam component's flexible bodies into the parts of the vehicle being built
    (``bodies``, ``joints``: dicts by name, edited in place; ``out``: the lists of extra bodies,
    joints and force elements, extended); returns {node: engine body} of the component."""
    source = component.source or component.name
    fe = reduce_bodies(component)
    for new, (donor, fe_names) in spec.split.items():
        bodies[donor], (mass, com, inertia) = _take_out(bodies[donor], fe, component, fe_names,
                                                        source)
        bodies[new] = Body(new, mass, com, inertia)
    for joint in spec.removed + spec.locked:
        if joint not in joints:
            raise ModelError(f"vehicle '{vehicle.name}' has no joint '{joint}' (the {name}'s "
                             "per-body map names it)")
    for joint in spec.removed:
        del joints[joint]
    for joint in spec.locked:
        joints[joint] = replace(joints[joint], locked=True)
    welds = {node: head if body == "head" else body for node, body in spec.welds.items()}
    built = body_elements(component, fe, spec.hangs, welds, spec.open_springs, spec.carried)
    for extra, what in zip(out, (built.bodies, built.joints, built.elements)):
        extra += what
    return built.node_bodies
