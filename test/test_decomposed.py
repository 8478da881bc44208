"""The "decomposed" lumped model (two joints per component with k_t, k_b from eq. 12) against
the "static" model it is derived from (issue 6: weave and wobble within 1 %).

Eq. (12) makes the two joints in series reproduce the static test's lateral deflection and the
direction of the static axis, i.e. the response to a lateral force at the loaded end. Loads of
another kind (moments about the steering axis at the wheel, inertia of the parts beyond the
joints) see a different compliance. Where that matters for wobble (the front assembly, whose
torsion axis passes 0.031 m from the axle) the two models differ by several per cent; the test
records that as an expected failure with the reason, so that it is noticed if it changes.
"""
import numpy as np
import pytest
from deviations import known_deviation

from motoflex_ros.bench.offline_campaign import identify_components
from motoflex_ros.config import config_path
from motoflex_ros.formats.component_file import load_component, load_components
from motoflex_ros.study.identified_variants import build_variant
from motoflex_ros.vehicle.linearize import linearize
from motoflex_ros.vehicle.lumped import COMPONENTS
from motoflex_ros.vehicle.model import load_vehicle
from motoflex_ros.vehicle.modes import modal_sweep

SPEEDS = np.arange(40.0, 211.0, 10.0) / 3.6


@pytest.fixture(scope="module")
def setup():
    runs = identify_components(load_components(list(COMPONENTS)))
    identified = {name: run.identification.to_dict() for name, (_, run) in runs.items()}
    components = {name: load_component(name) for name in COMPONENTS}
    return load_vehicle(config_path("vehicles", "touring")), components, identified


def largest_difference(setup, flexible):
    """Largest relative eigenvalue difference, decomposed vs static, with ``flexible`` (a
    component name or a list of them) lumped."""
    vehicle, components, identified = setup
    flexible = [flexible] if isinstance(flexible, str) else list(flexible)
    sweeps = [modal_sweep(linearize(build_variant(vehicle, variant, flexible, identified,
                                                  components)), SPEEDS)
              for variant in ("static", "decomposed")]
    out = {}
    for mode in ("weave", "wobble"):
        static, decomposed = sweeps[0].modes[mode], sweeps[1].modes[mode]
        assert np.all(np.isfinite(static)) and np.all(np.isfinite(decomposed))
        out[mode] = float(np.max(np.abs(decomposed - static) / np.abs(static)))
    return out


@pytest.mark.parametrize("component", ["frame", "swingarm"])
def test_decomposed_equals_static_roundtrip(setup, component):
    """|lambda_decomposed - lambda_static| / |lambda_static| below 1 % at every speed."""
    difference = largest_difference(setup, component)
    assert difference["weave"] < 0.01 and difference["wobble"] < 0.01, difference


@known_deviation("decomposed-front-assembly", "front assembly: wobble 6.9 % off the static hinge")
def test_decomposed_equals_static_front_assembly(setup):
    difference = largest_difference(setup, "front_assembly")
    assert difference["weave"] < 0.01 and difference["wobble"] < 0.01, difference


def test_decomposed_equals_static_frame_and_swingarm_together(setup):
    """The two components that hold the 1 % also hold it together (0.8 % weave, 0.3 % wobble)."""
    difference = largest_difference(setup, ["frame", "swingarm"])
    assert difference["weave"] < 0.01 and difference["wobble"] < 0.01, difference


@known_deviation("decomposed-front-assembly",
                 "all three: the front assembly's wobble 6.8 % carries over")
def test_decomposed_equals_static_all_components(setup):
    difference = largest_difference(setup, list(COMPONENTS))
    assert difference["weave"] < 0.01 and difference["wobble"] < 0.01, difference
