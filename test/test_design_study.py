"""``motoflex study design`` (issue 26): the exact update, a known optimum, bad design spaces.

- The cheap update of the flexible motorcycle's E(v), A(v) (design_update) equals a full
  re-reduction and linearization of the flexible motorcycle with the changed components, to
  1e-8 on every finite eigenvalue, for random designs inside the bounds.
- A one-variable problem with a known answer: least mass subject to weave_high >= its value at
  a chosen wall thickness t*; the index rises with the wall and so does the mass, so the optimum
  is t*, which bisection on the engine finds independently; SLSQP must find it.
- Bad design spaces are refused naming the file and the key.
"""
import math
from dataclasses import replace

import numpy as np
import pytest
import scipy.linalg
import yaml

from motoflex_ros.cli.inputs import study_speeds
from motoflex_ros.config import config_path, resolve_config
from motoflex_ros.errors import ConfigError
from motoflex_ros.formats.component_file import load_component
from motoflex_ros.formats.design_space_file import (
    design_component_text,
    held_members_mass,
    load_design_space,
)
from motoflex_ros.study.design_evaluate import DesignBatch, design_evaluator
from motoflex_ros.study.design_search import DesignProblem, index_floors, least_mass
from motoflex_ros.study.design_space import component_with, design_configs, members_mass
from motoflex_ros.study.design_update import design_superelement
from motoflex_ros.vehicle import lumped
from motoflex_ros.vehicle.dynamics import build_system
from motoflex_ros.vehicle.linearize import linearize_at
from motoflex_ros.vehicle.model import load_vehicle
from motoflex_ros.vehicle.variants import flexible_vehicle


@pytest.fixture(scope="module")
def space():
    return load_design_space("touring")


@pytest.fixture(scope="module")
def setup(space):
    vehicle = load_vehicle(resolve_config("vehicles", "touring"))
    components = {n: load_component(n) for n in lumped.COMPONENTS}
    evaluator = design_evaluator(space, vehicle, components, study_speeds(5.0, 10.0),
                                 held_members_mass(space, components))
    return space, vehicle, components, evaluator


def _finite_eigenvalues(E, A):
    alpha, beta = scipy.linalg.eig(A, E, right=False, homogeneous_eigvals=True)
    finite = np.abs(beta) > 1e-12 * np.maximum(np.abs(alpha), 1.0)
    return alpha[finite] / beta[finite]


@pytest.mark.slow  # the engine's recording linearization (6-10 s), then two full ones (1.5 s)
def test_design_update_equals_full_linearization(setup):
    space, vehicle, components, evaluator = setup
    engine = evaluator.engine
    rng = np.random.default_rng(26)
    for speed in (40.0 / 3.6, 190.0 / 3.6):
        x = space.lower + rng.random(len(space.names)) * (space.upper - space.lower)
        changed = {c: component_with(cfg, space.sources[c])
                   for c, cfg in design_configs(space, x).items()}
        E_c, A_c = engine.coefficients(engine.superelements(changed))
        powers = speed ** np.arange(3)
        E_cheap, A_cheap = np.tensordot(powers, E_c, 1), np.tensordot(powers, A_c, 1)
        full = {**components, **changed}
        model = flexible_vehicle(vehicle, {n: design_superelement(c, engine.n_modes[n])
                                           for n, c in full.items()})
        E_full, A_full = linearize_at(build_system(model), speed)
        # the update is not trivially zero: the design moves the matrices
        E_nom = np.tensordot(powers, engine.E_coeffs, 1)
        assert np.max(np.abs(E_full - E_nom)) > 1e-3 * np.max(np.abs(E_full))
        assert np.max(np.abs(E_cheap - E_full)) <= 1e-12 * np.max(np.abs(E_full))
        assert np.max(np.abs(A_cheap - A_full)) <= 1e-12 * np.max(np.abs(A_full))
        cheap = _finite_eigenvalues(E_cheap, A_cheap)
        ref = _finite_eigenvalues(E_full, A_full)
        assert len(cheap) == len(ref)
        gaps = [np.min(np.abs(ref - lam)) / max(abs(lam), 1.0) for lam in cheap]
        assert max(gaps) < 1e-8


def test_members_mass_analytic(space):
    # one tube member by hand: rho pi/4 (D^2 - (D - 2t)^2) L
    cfg = {"nodes": {"a": [0.0, 0.0, 0.0], "b": [0.0, 0.0, 0.5]},
           "materials": {"al": {"rho": 2700.0}},
           "sections": {"s": {"shape": "tube", "outer_diameter": 0.05,
                              "wall_thickness": 0.004}},
           "members": [{"from": "a", "to": "b", "section": "s", "material": "al"}]}
    want = 2700.0 * math.pi / 4.0 * (0.05**2 - 0.042**2) * 0.5
    assert members_mass(cfg) == pytest.approx(want, rel=1e-12)
    # thinner walls everywhere: lighter
    assert sum(members_mass(c) for c in design_configs(space, space.lower).values()) < \
        sum(members_mass(space.configs[c]) for c in space.components())


@pytest.mark.slow  # the engine (6-10 s), then about 3 s: a bisection and an SLSQP run
def test_least_mass_finds_known_optimum(setup):
    space, _, components, evaluator = setup
    name = "front_assembly.slider.wall_thickness"
    one = replace(space, variables=tuple(v for v in space.variables if v.name == name),
                  floors={})
    held = sum(members_mass(space.configs[c]) for c in space.components()
               if c != "front_assembly")
    ev = replace(evaluator, space=one, held_mass_kg=held)
    lo, hi = one.lower[0], one.upper[0]
    target = lo + 0.3 * (hi - lo)

    def weave_high(t):
        return float(ev(DesignBatch(one.names, np.array([[t]])).values())["weave_high"][0])

    floor = weave_high(target)
    assert weave_high(lo) < floor < weave_high(hi)        # bracketed: the floor binds
    a, b = lo, hi                                        # bisection on the engine
    for _ in range(12):
        mid = 0.5 * (a + b)
        a, b = (mid, b) if weave_high(mid) < floor else (a, mid)
    root = 0.5 * (a + b)
    assert root == pytest.approx(target, abs=1e-3 * (hi - lo))
    problem = DesignProblem(ev, floors={"weave_high": floor})
    x, result = least_mass(problem, maxiter=30)
    assert result.success
    assert x[0] == pytest.approx(root, abs=3e-3 * (hi - lo))
    assert x[0] >= root - 1e-3 * (hi - lo)           # the floor is met, not undercut


def test_component_file_round_trip(space, tmp_path):
    x = 0.5 * (space.lower + space.upper)
    path = tmp_path / "front_assembly.yaml"
    path.write_text(design_component_text(space, "front_assembly", x, "test design"))
    loaded = load_component(str(path))
    built = component_with(design_configs(space, x)["front_assembly"],
                           space.sources["front_assembly"])
    got, want = loaded.clamped_reduced(), built.clamped_reduced()
    np.testing.assert_allclose(got.frequencies_hz, want.frequencies_hz, rtol=1e-12)
    sections = yaml.safe_load(path.read_text())["sections"]
    assert sections["slider"]["wall_thickness"] == pytest.approx(x[space.names.index(
        "front_assembly.slider.wall_thickness")], rel=1e-15)


def _space_file(tmp_path, edit):
    data = yaml.safe_load(config_path("design", "touring").read_text())
    edit(data)
    path = tmp_path / "space.yaml"
    path.write_text(yaml.safe_dump(data))
    return path


@pytest.mark.parametrize("edit, key, words", [
    (lambda d: d["components"]["frame"]["sections"].update({"seat_rail": {
        "wall_thickness": [0.001, 0.002]}}), "components.frame.sections.seat_rail",
     "no section 'seat_rail'"),
    (lambda d: d["components"]["swingarm"]["sections"]["arm"].update({
        "outer_diameter": [0.05, 0.06]}), "components.swingarm.sections.arm.outer_diameter",
     "has no 'outer_diameter'"),
    (lambda d: d["components"]["swingarm"]["sections"]["arm"].update({
        "wall_thickness": [0.006, 0.003]}), "components.swingarm.sections.arm.wall_thickness",
     "low < high"),
    (lambda d: d["components"]["frame"]["sections"]["downtube"].update({
        "outer_diameter": [0.07, 3.0]}), "components.frame.sections.downtube.outer_diameter",
     "<= 2"),
    (lambda d: d["constraints"].update({"capsize_low": "nominal"}), "constraints.capsize_low",
     "unknown stability index"),
    (lambda d: d["components"]["frame"]["sections"]["downtube"].update({
        "wall_thickness": [0.003, 0.045]}), "components.frame.sections.downtube.wall_thickness",
     "half"),
])
def test_bad_design_space_named(tmp_path, edit, key, words):
    path = _space_file(tmp_path, edit)
    with pytest.raises(ConfigError) as info:
        load_design_space(str(path))
    assert str(path) in str(info.value) and key in str(info.value) and words in str(info.value)


@pytest.mark.slow  # the engine (6-10 s) for the nominal design's indices
def test_infeasible_nominal_named(setup, tmp_path):
    space, evaluator = setup[0], setup[3]
    nominal = {k: float(v[0]) for k, v in evaluator(
        DesignBatch(space.names, space.nominal[None]).values()).items()}
    too_high = space.with_floors({**space.index_floors,
                                  "wobble_high": nominal["wobble_high"] + 0.5})
    with pytest.raises(ConfigError) as info:
        index_floors(too_high, nominal)
    assert space.source in str(info.value) and "constraints.wobble_high" in str(info.value)
    assert "infeasible" in str(info.value)
