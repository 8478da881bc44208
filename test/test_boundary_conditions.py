"""One set of boundary conditions for bench and vehicle (issue 12): docs/boundary-conditions.md
checked against the models. Every bench clamp and loaded end of a component lies (1 mm) on the
vehicle joint or wheel the table names, and the table lists every row checked here."""
from pathlib import Path

import numpy as np
import pytest

from motoflex_ros.config import config_path
from motoflex_ros.formats.component_file import load_component
from motoflex_ros.structures.bodies import body_mass_properties, split_bodies
from motoflex_ros.vehicle import lumped
from motoflex_ros.vehicle.model import load_vehicle
from motoflex_ros.vehicle.superelement import follower_masks

DOC = Path(__file__).resolve().parents[1] / "docs" / "boundary-conditions.md"
TOLERANCE = 1e-3     # [m], the vehicle's own tolerance for meeting points

# component: [(node, "joint"|"wheel", vehicle name)], as the table's rows
AT_THE_SAME_POINT = {
    "frame": [("steering_head", "joint", "steer")],
    "front_assembly": [("steering_head", "joint", "steer"),
                       ("arm_pivot", "joint", "telelever_arm_pivot"),
                       ("arm_pivot_left", "axis", "telelever_arm_pivot"),
                       ("arm_pivot_right", "axis", "telelever_arm_pivot"),
                       ("lower_joint_fork", "joint", "telelever_ball"),
                       ("front_axle", "wheel", "front")],
    "swingarm": [("swingarm_pivot", "joint", "swingarm_pivot"),
                 ("pivot_left", "axis", "swingarm_pivot"),
                 ("pivot_right", "axis", "swingarm_pivot"),
                 ("strut_frame", "joint", "torque_strut_mount"),
                 ("carrier_pivot", "joint", "wheel_carrier_pivot"),
                 ("strut_rear", "joint", "torque_strut_ball"),
                 ("rear_axle", "wheel", "rear")],
}


@pytest.fixture(scope="module")
def vehicle():
    return load_vehicle(config_path("vehicles", "touring"))


def _gap(vehicle, point, kind, name):
    """Distance [m] of a component point from a wheel centre, a joint point or a joint axis."""
    if kind == "wheel":
        return np.linalg.norm(point - next(w.centre for w in vehicle.wheels if w.name == name))
    joint = next(j for j in vehicle.joints if j.name == name)
    r = point - joint.point
    if kind == "axis":
        r = r - (r @ joint.axis) * joint.axis
    return np.linalg.norm(r)


@pytest.mark.parametrize("component", sorted(AT_THE_SAME_POINT))
def test_bench_points_are_vehicle_joints(vehicle, component):
    comp = load_component(component)
    points = {n: comp.origin + comp.node_xyz[i] for n, i in comp.node_names.items()}
    for node, kind, name in AT_THE_SAME_POINT[component]:
        gap = _gap(vehicle, points[node], kind, name)
        assert gap < TOLERANCE, f"{component}.{node} is {gap * 1e3:.2f} mm from {kind} {name}"


@pytest.mark.parametrize("component", sorted(AT_THE_SAME_POINT))
def test_bench_clamps_and_loaded_end_are_in_the_table(component):
    comp = load_component(component)
    names = {i: n for n, i in comp.node_names.items()}
    checked = {node for node, _, _ in AT_THE_SAME_POINT[component]}
    text = DOC.read_text()
    rows = [line for line in text.splitlines() if line.startswith(f"| {component} |")]
    assert names[comp.loaded_end] in checked
    for node, _, name in AT_THE_SAME_POINT[component]:
        assert any(node in row and f"`{name}`" in row for row in rows), (component, node)
    for clamp in comp.clamp_nodes:          # every clamp is in a row (frame: engine mounts)
        assert any(names[clamp] in row for row in rows), (component, names[clamp])


def test_frame_clamps_are_on_the_rear_frame_that_carries_arm_and_swingarm(vehicle):
    """The frame's bench clamps (engine mounts) are on the body its superelement is welded to,
    the rear frame, which also carries the longitudinal arm and the swingarm (paper Sect. 4.1:
    the frame's two bodies are the head and the engine side)."""
    assert lumped.SUPERELEMENT_PARENT["frame"] == "frame"
    parents = {j.name: j.parent for j in vehicle.joints}
    assert parents["telelever_arm_pivot"] == parents["swingarm_pivot"] == "frame"
    assert parents["torque_strut_mount"] == "frame"


def test_swingarm_superelement_is_welded_where_it_is_clamped(vehicle):
    """The swingarm's superelement hangs from the main arm, which the locked pivot holds to the
    frame: the bench's pivot clamp."""
    parent = lumped.SUPERELEMENT_PARENT["swingarm"]
    pivot = next(j for j in vehicle.joints if j.name == "swingarm_pivot")
    assert pivot.child == parent and pivot.locked


def _follows(component):
    """{node index: vehicle body} the flexible motorcycle moves each node of ``component``
    rigidly with (its body of Table A.1, superelement.follower_masks)."""
    masks = follower_masks(component, lumped.SUPERELEMENT_PARENT[component.name],
                           lumped.SUPERELEMENT_FOLLOWS.get(component.name))
    return {int(n): body for body, mask in masks.items() for n in np.flatnonzero(mask)}


def _elastic_body_nodes(component, node):
    """The nodes of the body of ``node`` (paper Table A.1); for a node held by springs alone
    (a clamp such as the frame side of the head bearing), the nodes it is sprung to."""
    groups = split_bodies(component.structure)
    group = next(g for g in groups if node in g)
    if len(group) > 1:
        return group
    return tuple(b if a == node else a for a, b, _ in component.structure.springs
                 if node in (a, b))


@pytest.mark.parametrize("component", sorted(AT_THE_SAME_POINT))
def test_each_body_moves_with_the_vehicle_body_at_its_joints(vehicle, component):
    """Bench and vehicle see the same structure: every clamp, joint point and loaded end of a
    component belongs to a body (Table A.1) that the flexible motorcycle moves rigidly with
    a body of the vehicle joint (parent or child) or wheel at that point. Before the per-body
    rigid motion the whole front assembly, its arm on the frame's pivot included, moved with
    the steered lower fork."""
    comp = load_component(component)
    follows = _follows(comp)
    joints = {j.name: j for j in vehicle.joints}
    wheels = {w.name: w for w in vehicle.wheels}
    for node_name, kind, name in AT_THE_SAME_POINT[component]:
        at_point = ({wheels[name].carrier} if kind == "wheel"
                    else {joints[name].parent, joints[name].child})
        for node in _elastic_body_nodes(comp, comp.node_names[node_name]):
            assert follows[node] in at_point, (node_name, follows[node], at_point)


def _mass_following(component, body):
    """Rigid-body mass [kg], centre of mass [m] (vehicle frame) and inertia about it [kg m^2]
    of the FE nodes that the flexible motorcycle moves with vehicle ``body`` (consistent beam
    mass matrices, rigid parts included; clamped and linked nodes keep their mass)."""
    nodes = sorted(n for n, b in _follows(component).items() if b == body)
    mass, com, inertia = body_mass_properties(component.structure, nodes)
    return mass, com + component.origin, inertia


def test_flexible_and_lumped_front_move_the_same_lower_fork(vehicle):
    """The lumped front models move the whole lower fork body on their hinge (Sect. 5.2.2);
    in the flexible motorcycle the FE lower fork (sliders, lower bridge, legs, axle,
    calipers, casting) follows the deformation: same mass and centre of mass to 1e-9."""
    assert lumped.MOUNTS["front_assembly"][0] == "lower_fork"
    body = next(b for b in vehicle.bodies if b.name == "lower_fork")
    mass, com, _ = _mass_following(load_component("front_assembly"), "lower_fork")
    assert mass == pytest.approx(body.mass, rel=1e-9)
    assert np.allclose(com, body.com, rtol=0, atol=1e-9)


def test_swingarm_bodies_weigh_what_the_vehicle_bodies_do(vehicle):
    """The Paralever's vehicle bodies are the swingarm's FE bodies (main arm, torque strut,
    wheel carrier): mass, centre of mass and inertia to 1e-9, so that what follows the
    deformation in the flexible motorcycle is what its rigid bodies and the lumped models
    move (until issue 12 the vehicle's were [TUM]'s 10.07 kg, the FE's 11.28 kg)."""
    comp = load_component("swingarm")
    bodies = {b.name: b for b in vehicle.bodies}
    for body in ("swingarm", "torque_strut", "wheel_carrier"):
        mass, com, inertia = _mass_following(comp, body)
        assert mass == pytest.approx(bodies[body].mass, rel=1e-9), body
        assert np.allclose(com, bodies[body].com, rtol=0, atol=1e-9), body
        assert np.allclose(inertia, bodies[body].inertia, rtol=0, atol=1e-9), body
