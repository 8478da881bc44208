"""``study sensitivity --nominal principal`` (issue 22): the factorial on the principal hinges'
stiffnesses, its factors named after the paper's, its runs the principal motorcycle's."""
from types import SimpleNamespace

import numpy as np
import pytest

from motoflex_ros.cli.study import agreement
from motoflex_ros.config import config_path
from motoflex_ros.formats.component_file import load_component
from motoflex_ros.identify.principal import principal_hinges
from motoflex_ros.study.identified_variants import build_variant, carried_by_component
from motoflex_ros.study.motorcycle import (
    principal_factors,
    principal_study,
    with_principal_stiffness,
)
from motoflex_ros.vehicle import lumped
from motoflex_ros.vehicle.linearize import linearize
from motoflex_ros.vehicle.model import load_vehicle
from motoflex_ros.vehicle.modes import modal_sweep

SPEEDS = np.array([60.0, 130.0, 200.0]) / 3.6


@pytest.fixture(scope="module")
def motorcycle():
    """(vehicle, components, results with the FE models' principal hinges, no bench)."""
    vehicle = load_vehicle(config_path("vehicles", "touring"))
    components = {name: load_component(name) for name in lumped.COMPONENTS}
    carried = carried_by_component(vehicle, components)
    identified = {}
    for name, component in components.items():
        reduced = component.clamped_reduced()
        c = np.column_stack([reduced.static_end_motion(w)[[1, 3, 5]]
                             for w in np.eye(6)[[1, 3, 5]]])
        _, rows = principal_hinges(0.5 * (c + c.T), carried[name].metric(reduced.q0), reduced.q0)
        identified[name] = {"principal": {"identified": True, "hinges": [
            dict(zip(("l", "beta", "b", "k"), map(float, r))) for r in rows]}}
    return vehicle, components, identified


def test_factors_are_named_after_the_axes_they_stand_for(motorcycle):
    """Front assembly: the soft hinge along the fork is k_ta, the stiff one across it k_ba;
    swingarm: the bending-like hinge first; frame: one hinge (its metric has one direction)."""
    factors = principal_factors(motorcycle[2])
    assert factors == {"k_tf": ("frame", 0), "k_ta": ("front_assembly", 0),
                       "k_ba": ("front_assembly", 1), "k_bs": ("swingarm", 0),
                       "k_ts": ("swingarm", 1)}


def test_principal_study_runs_are_the_principal_motorcycle(motorcycle):
    """A run of the study (the superposed pencil) against the modal sweep of the principal
    variant built with those stiffnesses (a second formulation)."""
    vehicle, components, identified = motorcycle
    setup = principal_study(vehicle, components, identified, SPEEDS)
    values = dict(setup.nominal)
    values["k_ba"] *= 1.1
    values["k_ta"] *= 0.9
    runs = setup.study({f: np.array([v]) for f, v in values.items()})
    model = build_variant(vehicle, "principal", list(lumped.COMPONENTS),
                          with_principal_stiffness(identified, values,
                                                   principal_factors(identified)), components)
    direct = modal_sweep(linearize(model), SPEEDS)
    for mode in ("weave", "wobble"):
        np.testing.assert_allclose(runs[mode][0], direct.modes[mode], rtol=1e-6)


def test_agreement_marks_a_factor_the_principal_study_lacks():
    flexible = SimpleNamespace(pearson={"wobble_low": {"k_ta": -0.9, "k_bf": 0.2}})
    principal = SimpleNamespace(pearson={"wobble_low": {"k_ta": -1.0}})
    table = agreement(principal, flexible)["wobble_low"]
    assert table["k_ta"]["verdict"] == "same sign"
    assert table["k_bf"] == {"lumped": None, "flexible": 0.2, "difference": None,
                             "verdict": "no such factor"}
