"""Issue 22 (1): the per-body motorcycle's sensitivity to the front joint links' tilt stiffness.
The sweep itself (one 85 s per-body linearization per factor) runs from
tools/front_bridge_rocking.py; here the cheap facts it rests on (0.1 s each): the factor scales
exactly the two joint links' rotational springs (300 N m/rad nominal, the estimate in
config/components/front_assembly.yaml), and the fork bridge rocking on the freed head is held by
those links alone: its rocking stiffness goes to zero in proportion to the factor (a rocking
mode's frequency as its square root), while at large factors the structure in series caps it."""
import numpy as np
import pytest

from motoflex_ros.config import config_path
from motoflex_ros.formats.component_file import load_component
from motoflex_ros.study.identified_variants import build_variant
from motoflex_ros.study.tilt_stiffness import (
    JOINT_LINKS,
    PARTS,
    TiltSweep,
    bridge_rocking_stiffness,
    held_bridge,
    with_joint_link_tilt,
)
from motoflex_ros.vehicle.model import load_vehicle


def _blocks(component):
    names = component.node_names
    out = {}
    for n1, n2, block in component.structure.springs:
        out[frozenset((n1, n2))] = np.array(block, float)
    links = [frozenset((names[a], names[b])) for a, b in JOINT_LINKS]
    return out, links


@pytest.mark.parametrize("part", PARTS)
def test_factor_scales_only_the_joint_links_rotations(part):
    """"rotation": the links' 3 x 3 rotational blocks (300 N m/rad about every axis) times the
    factor; "tilt": times the factor about the axes normal to the stanchion, unchanged about
    the stanchion's own axis; every other spring, and the translations, unchanged; the
    component given is left as it was (a changed copy comes back)."""
    component = load_component("front_assembly")
    nominal, links = _blocks(component)
    scaled, _ = _blocks(with_joint_link_tilt(7.0, component, part=part))
    assert set(nominal) == set(scaled)
    kept, _ = _blocks(component)
    for key, block in nominal.items():
        np.testing.assert_array_equal(kept[key], block)
    for (_, stanchion), key in zip(JOINT_LINKS, links):
        block = nominal[key][3:, 3:]
        np.testing.assert_allclose(np.linalg.eigvalsh(block), [300.0] * 3)
        xyz = component.structure.xyz
        names = component.node_names
        axis = xyz[names[stanchion]] - xyz[names[stanchion.replace("top", "upper_bushing")]]
        axis = axis / np.linalg.norm(axis)
        normal = np.cross(axis, [0.0, 1.0, 0.0])
        normal /= np.linalg.norm(normal)
        rot = scaled[key][3:, 3:]
        assert axis @ rot @ axis == pytest.approx(300.0 * (7.0 if part == "rotation" else 1.0))
        assert normal @ rot @ normal == pytest.approx(300.0 * 7.0)
        np.testing.assert_array_equal(scaled[key][:3], nominal[key][:3])
    for key, block in nominal.items():
        if key not in links:
            np.testing.assert_array_equal(scaled[key], block)


def test_bridge_rocking_is_held_by_the_joint_links_alone():
    """Pitch and roll of the bridge on the freed head (the third direction, steering, is free):
    stiffness per unit factor the same at s = 0.001 and 0.01 (to 0.1 %), so k_rock ~ s and a
    rocking frequency ~ sqrt(s) at small s; at s = 1000 the structure in series holds it to
    under a tenth of that proportional stiffness."""
    front = load_component("front_assembly")
    small, smaller = bridge_rocking_stiffness(front, 0.01), bridge_rocking_stiffness(front, 0.001)
    stiff = bridge_rocking_stiffness(front, 1000.0)
    for k in (small, smaller):
        assert abs(k[0]) < 1e-4 * k[1]           # steering about the head: free
    np.testing.assert_allclose(small[1:] / 0.01, smaller[1:] / 0.001, rtol=1e-3)
    assert 100.0 < small[1] / 0.01 < 2 * 300.0  # N m/rad per unit factor: two links' order
    assert np.all(stiff[1:] / 1000.0 < 0.1 * small[1:] / 0.01)


def test_held_bridge_makes_only_the_head_revolute():
    vehicle = load_vehicle(config_path("vehicles", "touring"))
    per_body = build_variant(vehicle, "flexible_bodies", ["front_assembly"], {},
                             {"front_assembly": load_component("front_assembly")})
    held = held_bridge(per_body)
    kinds = {j.name: (j.kind, h.kind) for j, h in zip(per_body.joints, held.joints)}
    assert kinds["steer"] == ("spherical", "revolute")
    assert all(a == b for name, (a, b) in kinds.items() if name != "steer")


def test_least_damped_takes_the_largest_real_part_and_marks_an_unnamed_mode():
    speeds = np.array([10.0, 20.0, 30.0])
    weave = np.array([[-1 + 2j, -0.5 + 2j, -0.7 + 2j], [np.nan, np.nan, np.nan]])
    sweep = TiltSweep("tilt", np.array([1.0, 3.0]), speeds, {"weave": weave, "wobble": weave},
                      {}, {})
    real, where = sweep.least_damped()["weave"]
    assert real[0] == -0.5 and where[0] == 20.0
    assert np.isnan(real[1]) and np.isnan(where[1])
