"""Craig-Bampton superelements in the vehicle engine (the flexible ground truth, Sect. 4.1).

- A test component of two very stiff parts joined by one soft hinge, as a superelement in the
  touring motorcycle, gives the weave and wobble of the lumped model with that hinge (0.1 %).
- The real components' superelements with their stiffness scaled up converge to the rigid
  motorcycle (the convergence is shown: error falls with the scale).
"""
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from motoflex_ros.config import config_path
from motoflex_ros.formats.component_file import load_component
from motoflex_ros.inertia import parallel_axis
from motoflex_ros.vehicle import lumped
from motoflex_ros.vehicle.linearize import linearize
from motoflex_ros.vehicle.model import Body, Joint, load_vehicle
from motoflex_ros.vehicle.modes import modal_sweep
from motoflex_ros.vehicle.superelement import superelement_of
from motoflex_ros.vehicle.variants import flexible_vehicle

DATA = Path(__file__).parent / "data"
SPEEDS = np.arange(40.0, 211.0, 10.0) / 3.6


@pytest.fixture(scope="module")
def vehicle():
    return load_vehicle(config_path("vehicles", "touring"))


def part_mass_properties(mass, cg, inertia_diag):
    return Body("rear_flex", mass, np.asarray(cg, float), np.diag(inertia_diag))


def lumped_hinge_vehicle(vehicle, component):
    """The same hinge as a lumped revolute joint; the carried part moves onto the new body."""
    origin = component.origin
    part = part_mass_properties(4.0, origin + np.array([-0.50, -0.05, -0.03]),
                                [0.02, 0.03, 0.025])
    arm = vehicle.body("swingarm")
    rest_mass = arm.mass - part.mass
    rest_com = (arm.mass * arm.com - part.mass * part.com) / rest_mass
    inertia = (arm.inertia + parallel_axis(arm.mass, arm.com - rest_com) - part.inertia
               - parallel_axis(part.mass, part.com - rest_com))
    rest = replace(arm, mass=rest_mass, com=rest_com, inertia=inertia)
    axis = np.array([0.6, 0.0, 0.8])
    hinge = Joint("hinge", "revolute", "swingarm", "rear_flex", axis,
                  origin + np.array([-0.30, 0.0, -0.02]), 2.0e4, 0.0)
    bodies = [rest if b.name == "swingarm" else b for b in vehicle.bodies] + [part]
    wheels = [replace(w, carrier="rear_flex") if w.name == "rear" else w
              for w in vehicle.wheels]
    return replace(vehicle, bodies=tuple(bodies), joints=vehicle.joints + (hinge,),
                   wheels=tuple(wheels))


def weave_wobble(model):
    sweep = modal_sweep(linearize(model), SPEEDS)
    return np.concatenate([sweep.modes["weave"], sweep.modes["wobble"]])


def test_soft_hinge_superelement_equals_lumped_joint(vehicle):
    component = load_component(DATA / "soft_hinge_swingarm.yaml")
    lumped.check_site(vehicle, "swingarm", lumped.site_of(component))
    se = superelement_of(component, "swingarm", zeta=0.0)
    flexible = weave_wobble(flexible_vehicle(vehicle, {"swingarm": se}))
    hinge = weave_wobble(lumped_hinge_vehicle(vehicle, component))
    rigid = weave_wobble(vehicle)
    assert np.all(np.isfinite(flexible)) and np.all(np.isfinite(hinge))
    # the hinge matters (so the comparison can fail) ...
    assert np.max(np.abs(hinge - rigid) / np.abs(rigid)) > 1e-2
    # ... and the superelement reproduces it
    assert np.max(np.abs(flexible - hinge) / np.abs(hinge)) < 1e-3


@pytest.mark.parametrize("name", lumped.COMPONENTS)
def test_stiff_superelement_converges_to_rigid_limit(vehicle, name):
    component = load_component(name)
    se = superelement_of(component, lumped.SUPERELEMENT_PARENT[name])
    rigid = weave_wobble(vehicle)
    errors = []
    for scale in (1e2, 1e4):
        model = flexible_vehicle(vehicle, {name: se.scaled(scale)})
        errors.append(np.max(np.abs(weave_wobble(model) - rigid) / np.abs(rigid)))
    assert errors[1] < errors[0] / 10 and errors[1] < 1e-3
