"""Bench tests loaded as the vehicle loads a component (issue 14): road_load through a rigid
lever at the tyre contact point, and the load-test identification (eqs. 1-8 with the load's
moment about the axis)."""
import copy

import numpy as np
import pytest
import scipy.sparse.linalg as spla
import yaml

from motoflex_ros.bench.load_tests import lever_wrench, load_test
from motoflex_ros.bench.offline_campaign import (
    only_tests,
    run_campaign,
    setup_campaign,
    with_sensor,
)
from motoflex_ros.bench.protocols import RoadLoadTest, load_protocol
from motoflex_ros.cli.inputs import motorcycle_components
from motoflex_ros.config import resolve_config
from motoflex_ros.errors import ConfigError
from motoflex_ros.identify.results import static_model
from motoflex_ros.study.load_variants import contact_point, road_load_tests
from motoflex_ros.vehicle import lumped
from motoflex_ros.vehicle.model import load_vehicle


@pytest.fixture(scope="module")
def setting():
    return load_vehicle(resolve_config("vehicles", "touring")), motorcycle_components()


def _fe_end_motion(component, wrench):
    """Second formulation: the full (unreduced) FE model, clamps fixed, solved for the wrench
    at the loaded end node (sparse direct solve) [m, rad]."""
    structure = copy.deepcopy(component.structure)
    for node in component.clamp_nodes:
        structure.clamp(node)
    assembled = structure.assemble()
    dofs = assembled.node_dofs(component.loaded_end)
    load = np.zeros(assembled.K.shape[0])
    load[dofs] = wrench
    return spla.spsolve(assembled.K.tocsc(), load)[dofs]


@pytest.mark.parametrize("name", ["frame", "front_assembly", "swingarm"])
def test_road_load_deflection_is_the_fe_compliance_of_the_lever_load(setting, name):
    """The road_load bench test (ramp and hold on the clamped reduced model, the markers read
    without noise) deflects the loaded end as the full FE model does under the lever's load:
    a lateral force at the tyre contact point of the static configuration moved to q0."""
    vehicle, components = setting
    component = components[name]
    setup = with_sensor(setup_campaign(component), noise_m=0.0, resolution_m=0.0)
    result = road_load_tests(vehicle, components, [name], {name: setup})[name]
    site = lumped.site_of(component)
    point = contact_point(vehicle, name) - site.origin
    np.testing.assert_allclose(result.wrench, lever_wrench(site.q0, point, [0, 1, 0]))
    expected = _fe_end_motion(component, result.force_n * result.wrench)
    error = np.linalg.norm(result.end_motion - expected) / np.linalg.norm(expected)
    assert error < 1e-4, (result.end_motion, expected)


def test_contact_point_is_a_rolling_radius_below_the_wheel_centre(setting):
    vehicle, _ = setting
    front = next(w for w in vehicle.wheels if w.name == "front")
    point = contact_point(vehicle, "front_assembly")
    assert point[2] == pytest.approx(front.centre[2] - front.radius)
    assert point[2] == pytest.approx(0.0, abs=1e-6)   # on the ground
    np.testing.assert_allclose(point[:2], front.centre[:2])


def test_load_test_with_the_papers_load_is_the_static_test(setting):
    """With the paper's load (F_y at q0: no lever) the load test is the static test: same
    samples, same sensor noise (seed), and m = b makes its k eq. (8)'s."""
    _, components = setting
    setup = setup_campaign(components["front_assembly"])
    lever = load_test(setup, [0, 1, 0, 0, 0, 0], "static", seed=3).model.values
    reading = run_campaign(only_tests(setup, ("static",)), seed=3).readings["static"]
    paper = static_model(reading, setup.reduced.q0)[0].values
    for key in ("l", "beta", "b", "k", "c"):
        assert lever[key] == pytest.approx(paper[key], rel=1e-9), key


def test_road_load_protocol_section(tmp_path):
    """The protocol's road_load: defaults (contact point, lateral, the static force), a point
    and direction given (normalised), and a zero direction refused naming the key."""
    assert load_protocol("front_assembly").road_load == RoadLoadTest()
    data = yaml.safe_load(resolve_config("protocols", "front_assembly").read_text())
    data["road_load"] = {"point_m": [0.2, 0.0, -0.7], "direction": [0.0, 2.0, 0.0],
                         "force_n": 200.0}
    path = tmp_path / "lever.yaml"
    path.write_text(yaml.safe_dump(data))
    spec = load_protocol(str(path)).road_load
    assert spec == RoadLoadTest((0.2, 0.0, -0.7), (0.0, 1.0, 0.0), 200.0)
    data["road_load"]["direction"] = [0.0, 0.0, 0.0]
    path.write_text(yaml.safe_dump(data))
    with pytest.raises(ConfigError, match="road_load.direction"):
        load_protocol(str(path))
