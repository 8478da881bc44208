"""The accuracy study (Sect. 5.2, eq. 18, Figs 8-9): lumped variants against the flexible
motorcycle, end to end through ``motoflex study accuracy`` and through the core."""
import json
import math

import numpy as np
import pytest
from deviations import known_deviation
from hostile import run_motoflex
from regression import expected

from motoflex_ros.bench.offline_campaign import identify_components
from motoflex_ros.config import config_path
from motoflex_ros.errors import ModelError
from motoflex_ros.formats.component_file import load_component, load_components
from motoflex_ros.study.accuracy import QUANTITIES, rms_error_percent
from motoflex_ros.study.identified_variants import carried_inertias
from motoflex_ros.study.lumped_accuracy import (
    ACCURACY_VARIANTS,
    CASES,
    PAPER_VARIANTS,
    accuracy_study,
    mode_errors,
)
from motoflex_ros.vehicle import lumped
from motoflex_ros.vehicle.model import load_vehicle

SPEEDS = np.arange(40.0, 211.0, 10.0) / 3.6


def identified_components():
    """The bench identification of the three components with their carried inertias (seed 0),
    as identification.json holds it."""
    components = load_components(["frame", "front_assembly", "swingarm"])
    carried = carried_inertias(components)
    runs = identify_components(components, carried=carried)
    return {name: run.identification.to_dict() for name, (_, run) in runs.items()}


@pytest.fixture(scope="module")
def identified_file(tmp_path_factory):
    path = tmp_path_factory.mktemp("ident") / "identification.json"
    path.write_text(json.dumps(identified_components()))
    return path


def motoflex(*args):
    return run_motoflex(args)


@pytest.fixture(scope="module")
def verb_run(identified_file, tmp_path_factory):
    """The verb as a user runs it (text), with --details: (e_RMS table, plot folder, printed
    text, per-component details)."""
    plots = tmp_path_factory.mktemp("plots")
    details = plots / "details.json"
    result = motoflex("study", "accuracy", "--identified", str(identified_file), "--details",
                      str(details), "--step-kmh", "10", "--plot", str(plots))
    assert result.returncode == 0, result.stderr
    data = json.loads(details.read_text())
    return data["errors"], plots, result.stdout, data["components"]


def test_accuracy_verb_json_is_the_table(verb_run, identified_file):
    """--json prints the table of --details ({case: {variant: {quantity: %}}}), here for one
    case (the cases are independent)."""
    result = motoflex("study", "accuracy", "--identified", str(identified_file), "--json",
                      "--step-kmh", "10", "--cases", "swingarm")
    assert result.returncode == 0, result.stderr
    table = json.loads(result.stdout)
    assert set(table) == {"swingarm"}
    for variant, values in table["swingarm"].items():
        assert values == pytest.approx(verb_run[0]["swingarm"][variant], abs=1e-9), variant


def test_accuracy_verb_end_to_end(verb_run):
    table, plots, *_ = verb_run
    assert set(table) == set(CASES)
    for case in CASES:
        assert set(table[case]) == set(ACCURACY_VARIANTS)
        for variant in ACCURACY_VARIANTS:
            values = table[case][variant]
            assert set(values) == set(QUANTITIES)
            assert all(np.isfinite(v) and v >= 0 for v in values.values())
    assert (plots / "fig8_accuracy.png").stat().st_size > 10_000
    assert (plots / "fig9_front_assembly.png").stat().st_size > 10_000


@known_deviation("front-assembly-static-hinge",
                 "front assembly: weave Re 3.4 vs 1.9 % (state of the art vs bending)")
def test_published_state_of_the_art_and_bending_alike_for_front_assembly(verb_run):
    """Sect. 5.2.2: for the front assembly the state-of-the-art and the bending models give
    very similar results (the bending axis is almost perpendicular to the fork)."""
    front = verb_run[0]["front_assembly"]
    for quantity in QUANTITIES:
        a, b = front["state_of_the_art"][quantity], front["bending"][quantity]
        assert abs(a - b) <= 0.25 * max(a, b) + 0.5, (quantity, a, b)


TIE = 0.01
"""Totals closer than 1 % (relative) are a tie at the resolution of eq. 18 over the grid: with
all components the static and the bending totals swapped places between the 10 km/h and the
1 km/h grids before issue 12's front assembly (48.49 vs 48.51 %, 48.43 vs 48.15 %); with it,
static is lowest on both (40.97 vs 42.08 %, 40.92 vs 41.68 %)."""


@pytest.mark.parametrize("case", [
    "frame", "all",
    pytest.param("front_assembly", marks=known_deviation(
        "front-assembly-static-hinge", "front assembly: bending 40.7 below static 42.7 %")),
    pytest.param("swingarm", marks=known_deviation(
        "swingarm-static-vs-bending", "swingarm: bending 3.66 % below static 4.25 %")),
])
def test_published_static_lowest_error_in_every_case(verb_run, case):
    """Sect. 5.2: the static model has the lowest e_RMS (sum of the four quantities) of the
    paper's four variants in each of the four cases; within TIE of the lowest counts as
    lowest."""
    totals = {v: sum(verb_run[0][case][v].values()) for v in PAPER_VARIANTS}
    assert totals["static"] <= min(totals.values()) * (1 + TIE), (case, totals)


@pytest.mark.regression
def test_swingarm_hinges_lack_the_fe_yaw_compliance(identified_file):
    """The measured cause of the swingarm's xfail above. A hinge's compliance at q0 is rank
    one, s s^T / k (s its unit twist there). The static test fits it to the FE's response to
    a lateral force at the axle, so its yaw compliance is C_yz^2 / C_yy (Cauchy-Schwarz: at
    most C_zz), 0.38 of the FE's; the bending hinge, softer, has 0.45 of it. The weave loads
    the rear axle with a yaw moment too, which no such hinge carries as the FE does."""
    fe, hinges = swingarm_hinge_compliances(json.loads(identified_file.read_text())["swingarm"])
    hinge = hinges["static"]            # the bench's load case, within the identification
    assert hinge[1, 1] == pytest.approx(fe[1, 1], rel=0.01)
    assert hinge[5, 1] == pytest.approx(fe[5, 1], rel=0.01)
    assert hinge[5, 5] == pytest.approx(fe[5, 1] ** 2 / fe[1, 1], rel=0.02)
    for test in ("static", "bending"):     # regression: the shares our code gave (the commit
        share = hinges[test][5, 5] / fe[5, 5]   # in test/regression_values.json)
        assert share == expected(f"swingarm_yaw_share.{test}"), (test, share)


def swingarm_hinge_compliances(found):
    """The swingarm's clamped FE end compliance at q0 (6 x 6, [m/N, rad/(N m)]) and the
    compliance s s^T / k of its static and bending hinges ``found`` (an identification.json
    entry) there."""
    comp = load_component("swingarm")
    reduced = comp.clamped_reduced()
    fe = np.column_stack([reduced.static_end_motion(e) for e in np.eye(6)])
    site = lumped.site_of(comp)
    hinges = {}
    for test in ("static", "bending"):
        point, axis = lumped.axis_in_vehicle(site, found[test]["l"], found[test]["beta"])
        twist = np.r_[np.cross(axis, site.origin + site.q0 - point), axis]
        hinges[test] = np.outer(twist, twist) / found[test]["k"]
    return fe, hinges


def test_published_frame_identified_models_beat_the_state_of_the_art(verb_run):
    """Sect. 5.2.1: the frame's state-of-the-art hinge (at the steering head, normal to the
    fork axis) has a relatively high error on the wobble real part; the identified models are
    significantly better. With the paper's load path (the longitudinal arm on the rear frame)
    ours: 4.8 % against 1.4-1.6 %."""
    frame = verb_run[0]["frame"]
    sota = frame["state_of_the_art"]["wobble_re"]
    for variant in ("static", "torsion", "bending"):
        assert frame[variant]["wobble_re"] < 0.5 * sota, (variant, frame[variant], sota)


@known_deviation("front-assembly-static-hinge",
                 "all flexible: static wobble Re 33.3 %, set by the front assembly")
def test_published_static_wobble_real_part_within_10_percent(verb_run):
    """Sect. 5.2.4: with all components flexible the static model's wobble real-part error is at
    most 10 %."""
    assert verb_run[0]["all"]["static"]["wobble_re"] <= 10.0


def test_core_errors_are_eq18_of_the_tracked_curves(identified_file):
    vehicle = load_vehicle(config_path("vehicles", "touring"))
    components = {"swingarm": load_component("swingarm")}
    identified = json.loads(identified_file.read_text())
    result = accuracy_study(vehicle, components, identified, SPEEDS, cases=("swingarm",),
                            variants=("static",))
    curves = result.curves["swingarm"]
    wobble_lu, wobble_fl = curves["static"]["wobble"], curves["flexible"]["wobble"]
    hand = (np.sqrt(np.mean((wobble_lu.real - wobble_fl.real) ** 2))
            / abs(np.mean(wobble_fl.real)) * 100)
    assert result.errors["swingarm"]["static"]["wobble_re"] == pytest.approx(hand, rel=1e-12)
    assert rms_error_percent(wobble_fl.real, wobble_fl.real) == 0.0
    same = mode_errors(curves["flexible"], curves["flexible"], "self")
    assert all(v == 0.0 for v in same.values())


def test_untracked_mode_is_an_error():
    curve = np.full(3, -1.0 + 10j)
    lost = curve.copy()
    lost[1] = np.nan
    with pytest.raises(ModelError, match="wobble is not tracked"):
        mode_errors({"weave": curve, "wobble": lost}, {"weave": curve, "wobble": curve}, "x")


def test_accuracy_verb_bad_input(tmp_path):
    assert motoflex("study", "accuracy", "--step-kmh", "0").returncode == 2
    partial = tmp_path / "partial.json"
    partial.write_text(json.dumps({"frame": {"static": {"l": 0.3}}}))
    result = motoflex("study", "accuracy", "--identified", str(partial))
    assert result.returncode == 2
    assert "front_assembly" in result.stderr or "frame.static" in result.stderr


# -- beyond the paper (issue 14): the fitted, road_load and vehicle_load hinges -------------

def _rss(values):
    return math.sqrt(sum(v * v for v in values.values()))


@pytest.mark.parametrize("case", CASES)
def test_fitted_hinge_within_2_percent_and_better_than_static(verb_run, case):
    """The hinge fitted to the flexible motorcycle (for 'all' the three components' own,
    unchanged) is within 2 % on each of the four quantities, its root sum of squares below
    the static hinge's, and no quantity more than 0.1 %-points worse than static's."""
    table = verb_run[0][case]
    fitted, static = table["fitted"], table["static"]
    assert max(fitted.values()) <= 2.0, fitted
    assert _rss(fitted) < _rss(static), (fitted, static)
    for quantity in QUANTITIES:
        assert fitted[quantity] <= static[quantity] + 0.1, (quantity, fitted, static)


def _printed_conditioning(text, component):
    """The conditioning table printed after 'fitted <component>:' {change: [4 values]} (it
    ends at the first line that is not a row of five numbers)."""
    lines = text.splitlines()
    start = next(i for i, line in enumerate(lines) if line.startswith(f"fitted {component}:"))
    rows = {}
    for line in lines[start + 4:]:
        parts = line.split()
        if len(parts) < 6 or not all(p.replace(".", "", 1).isdigit() for p in parts[-5:]):
            break
        rows[" ".join(parts[:-5])] = [float(v) for v in parts[-5:-1]]
    return rows


def test_conditioning_is_what_the_study_prints(verb_run, identified_file):
    """The conditioning the verb prints is that of --details, and each entry is eq. 18 of the
    lumped motorcycle with that one change, built and swept by the engine as the accuracy study
    does (front assembly: the six changes)."""
    from motoflex_ros.study.hinge_fit_problem import PERTURBATIONS
    from motoflex_ros.study.hinge_fit_result import with_fitted
    from motoflex_ros.study.hinge_geometry import hinge_of, perturbed
    from motoflex_ros.study.identified_variants import build_variant
    from motoflex_ros.study.lumped_accuracy import _weave_wobble, flexible_reference
    from motoflex_ros.vehicle import lumped

    _, _, text, components_details = verb_run
    for component, entry in components_details.items():
        reported = entry["fit"]["components"][component]["conditioning"]
        printed = _printed_conditioning(text, component)
        assert set(printed) == set(reported) | {"optimum"}
        for label, values in reported.items():
            assert printed[label] == pytest.approx([values[q] for q in QUANTITIES], abs=0.006)
    component = "front_assembly"
    vehicle = load_vehicle(config_path("vehicles", "touring"))
    comps = {component: load_component(component)}
    identified = json.loads(identified_file.read_text())
    speeds = np.append(np.arange(40.0, 210.0, 10.0), 210.0) / 3.6
    reference = flexible_reference(vehicle, comps, identified, [component], speeds)
    fit = components_details[component]["fit"]
    optimum = hinge_of(fit["components"][component]["fitted"])
    site = lumped.site_of(comps[component])

    class _One:
        hinges = {}

    for label, what, change in PERTURBATIONS:
        _One.hinges = {component: perturbed(site, optimum, what, change)}
        model = build_variant(vehicle, "fitted", [component], with_fitted(identified, [_One]),
                              comps)
        direct = mode_errors(_weave_wobble(model, speeds), reference, label)
        assert direct == pytest.approx(fit["components"][component]["conditioning"][label],
                                       abs=1e-4), label


def _compliance_ratio(component, entry, wrench=None):
    """(w . C_h . w) / (w . C . w): the fitted hinge's compliance under the wrench the
    component carries in the flexible motorcycle's wobble (or ``wrench``) against the clamped
    FE model's."""
    from motoflex_ros.study.hinge_geometry import end_compliance, hinge_compliance, hinge_of
    from motoflex_ros.vehicle import lumped

    comp = load_component(component)
    w = np.asarray(entry["vehicle_load"]["wrench_per_n"] if wrench is None else wrench)
    hinge = hinge_of(entry["fit"]["components"][component]["fitted"])
    return hinge_compliance(lumped.site_of(comp), hinge, w) / (w @ end_compliance(comp) @ w)


@pytest.mark.parametrize("component", [
    "frame", "front_assembly",
    pytest.param("swingarm", marks=known_deviation(
        "swingarm-fitted-hinge",
        "swingarm: the fitted hinge carries 0.16-0.22 of the FE compliance in weave"))])
def test_fitted_hinge_has_the_fe_compliance_under_the_wobble_wrench(verb_run, component):
    """The fitted hinge fits for a physical reason: under the wrench the component carries
    in the flexible motorcycle's wobble (100 km/h) its compliance w . C_h . w is within 10 %
    of the clamped FE model's w . C . w (C_h = s s^T / k, s the hinge's unit twist at q0)."""
    ratio = _compliance_ratio(component, verb_run[3][component])
    assert abs(ratio - 1.0) <= 0.10, ratio


def test_fe_end_stiffness_in_the_hinges_place(verb_run):
    """Where the single hinge stands against the FE model's whole end stiffness in its place
    (the lumped motorcycle with a 6 x 6 massless spring, K = C^-1): for the swingarm that
    spring fits the flexible motorcycle within 0.3 % on each quantity, better than the fitted
    hinge's largest (so the hinge's place is not what limits it); for the frame the spring
    leaves the static hinge's wobble real part (1.37 %, within 0.05 %-points: the static
    hinge already has the FE deflection under the head's lateral load, what remains is the
    frame's mass moving elastically), which the fitted hinge undercuts."""
    fits = {name: entry["fit"] for name, entry in verb_run[3].items()}
    spring = {name: fit["end_stiffness_errors"] for name, fit in fits.items()}
    assert max(spring["swingarm"].values()) <= 0.3, spring["swingarm"]
    assert max(spring["swingarm"].values()) < max(fits["swingarm"]["errors"].values())
    frame = verb_run[0]["frame"]
    assert spring["frame"]["wobble_re"] == pytest.approx(frame["static"]["wobble_re"],
                                                         abs=0.05)
    assert frame["fitted"]["wobble_re"] < 0.5 * spring["frame"]["wobble_re"]


def test_frame_fitted_hinge_has_the_fe_lateral_compliance_of_the_head(verb_run):
    """What weave and wobble determine of the frame's hinge: the steering head's lateral
    compliance b^2 / k, within 5 % of the FE model's (ours 0.97)."""
    lateral = np.array([0.0, 1.0, 0.0, 0.0, 0.0, 0.0])
    assert _compliance_ratio("frame", verb_run[3]["frame"], lateral) == pytest.approx(
        1.0, abs=0.05)


def test_vehicle_load_is_the_tyre_force_below_the_front_axle(verb_run):
    """What the issue says the bench misses: in the wobble the front assembly carries a lateral
    force acting about a wheel radius below the axle (M_x / F_y within 0.25-0.40 m), and the
    vehicle_load hinge identified with that load carries it with the FE model's compliance
    (within 1 %), the static hinge with a twentieth of it."""
    entry = verb_run[3]["front_assembly"]
    w = np.asarray(entry["vehicle_load"]["wrench_per_n"])
    assert abs(w[1]) == pytest.approx(1.0, abs=0.05)
    assert 0.25 <= w[3] / w[1] <= 0.40, w
    vehicle_hinge = {**entry, "fit": {"components": {"front_assembly": {
        "fitted": entry["vehicle_load"]}}}}
    static_hinge = {**entry, "fit": {"components": {"front_assembly": {
        "fitted": entry["fit"]["components"]["front_assembly"]["static"]}}}}
    assert _compliance_ratio("front_assembly", vehicle_hinge) == pytest.approx(1.0, abs=0.01)
    assert _compliance_ratio("front_assembly", static_hinge) < 0.1


@pytest.mark.parametrize("case", CASES)
def test_principal_hinges_within_2_percent_and_never_worse_than_static(verb_run, case):
    """Issue 22: the principal hinges from the bench (default sensor noise) within 2 % on each
    quantity in every case, never worse than static in total, equal to it for the frame (its
    metric passes no moment and reduces to the static test)."""
    table = verb_run[0][case]
    principal, static = table["principal"], table["static"]
    assert max(principal.values()) <= 2.0, principal
    assert sum(principal.values()) <= sum(static.values()) + 1e-9
    if case == "frame":
        for quantity in QUANTITIES:
            assert principal[quantity] == pytest.approx(static[quantity], abs=0.01)
