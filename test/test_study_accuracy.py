"""The accuracy study (Sect. 5.2, eq. 18, Figs 8-9): lumped variants against the flexible
motorcycle, end to end through ``motoflex study accuracy`` and through the core."""
import json
import subprocess
import sys

import numpy as np
import pytest

from motoflex_ros.bench.campaign import identify_components
from motoflex_ros.config import config_path
from motoflex_ros.errors import ModelError
from motoflex_ros.structures.components import load_component
from motoflex_ros.study.accuracy import rms_error_percent
from motoflex_ros.study.lumped_accuracy import (
    ACCURACY_VARIANTS,
    CASES,
    QUANTITIES,
    accuracy_study,
    mode_errors,
)
from motoflex_ros.vehicle.model import load_vehicle

SPEEDS = np.arange(40.0, 211.0, 10.0) / 3.6


@pytest.fixture(scope="module")
def identified_file(tmp_path_factory):
    runs = identify_components(["frame", "front_assembly", "swingarm"])
    data = {name: run.identification.to_dict() for name, (_, run) in runs.items()}
    path = tmp_path_factory.mktemp("ident") / "identification.json"
    path.write_text(json.dumps(data))
    return path


def motoflex(*args):
    return subprocess.run([sys.executable, "-m", "motoflex_ros.cli.main", *args],
                          capture_output=True, text=True)


@pytest.fixture(scope="module")
def verb_run(identified_file, tmp_path_factory):
    plots = tmp_path_factory.mktemp("plots")
    result = motoflex("study", "accuracy", "--identified", str(identified_file), "--json",
                      "--step-kmh", "10", "--plot", str(plots))
    assert result.returncode == 0, result.stderr
    return json.loads(result.stdout), plots


def test_accuracy_verb_end_to_end(verb_run):
    table, plots = verb_run
    assert set(table) == set(CASES)
    for case in CASES:
        assert set(table[case]) == set(ACCURACY_VARIANTS)
        for variant in ACCURACY_VARIANTS:
            values = table[case][variant]
            assert set(values) == set(QUANTITIES)
            assert all(np.isfinite(v) and v >= 0 for v in values.values())
    assert (plots / "fig8_accuracy.png").stat().st_size > 10_000
    assert (plots / "fig9_front_assembly.png").stat().st_size > 10_000


FRONT_CAUSE = ("bench and vehicle see the same structure (each body of the front assembly "
               "moves with the vehicle body that holds it, its arm on the frame's pivot; "
               "docs/boundary-conditions.md) and the per-body reductions equal the single FE "
               "model (test_structures_bodies); the compliance is where a Telelever has it and "
               "the lumped and flexible models move the same lower fork (1e-9). What is left is "
               "the load: the static hinge comes from a lateral force at the axle, while in "
               "wobble the fork carries the tyre's side force at the contact patch, 0.3 m lower, "
               "and the front wheel's gyroscopic moment (issue 14 measures both)")


@pytest.mark.xfail(strict=True, reason="ours (10 km/h grid): alike on wobble (f 3.3 vs 3.1 %, Re "
                   "37.8 vs 35.6 %) but not on the weave real part (3.4 vs 1.9 %) once the "
                   "state-of-the-art stiffness is measured, as the paper says, with a lateral "
                   "force at the axle; " + FRONT_CAUSE)
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
    pytest.param("front_assembly", marks=pytest.mark.xfail(strict=True, reason=(
        "ours (10 km/h grid): totals bending 40.7, static 42.7, state of the art 44.8 %, all "
        "set by the wobble real part (34-38 %); " + FRONT_CAUSE))),
    pytest.param("swingarm", marks=pytest.mark.xfail(strict=True, reason=(
        "ours (10 km/h grid): bending 3.66 % below static 4.25 % (weave real part 1.87 vs "
        "2.44 %): the two hinges are 5 deg and 1.7 cm apart, the bending one 16 % softer "
        "(1.13e5 vs 1.34e5 N m/rad) with the modal inertia of eq. 10; the flexible swingarm "
        "is welded to the frozen Paralever's main arm, the lumped hinge sits between the "
        "wheel carrier and the wheel; why the softer hinge fits the weave real part better is "
        "not yet known"))),
])
def test_published_static_lowest_error_in_every_case(verb_run, case):
    """Sect. 5.2: the static model has the lowest e_RMS (sum of the four quantities) in each of
    the four cases; within TIE of the lowest counts as lowest."""
    totals = {v: sum(verb_run[0][case][v].values()) for v in ACCURACY_VARIANTS}
    assert totals["static"] <= min(totals.values()) * (1 + TIE), (case, totals)


def test_published_frame_identified_models_beat_the_state_of_the_art(verb_run):
    """Sect. 5.2.1: the frame's state-of-the-art hinge (at the steering head, normal to the
    fork axis) has a relatively high error on the wobble real part; the identified models are
    significantly better. With the paper's load path (the longitudinal arm on the rear frame)
    ours: 4.8 % against 1.4-1.6 %."""
    frame = verb_run[0]["frame"]
    sota = frame["state_of_the_art"]["wobble_re"]
    for variant in ("static", "torsion", "bending"):
        assert frame[variant]["wobble_re"] < 0.5 * sota, (variant, frame[variant], sota)


@pytest.mark.xfail(strict=True, reason="ours (10 km/h grid): 33.3 % with all components "
                   "flexible, set by the front assembly (34.0 % alone; frame 1.4 %, swingarm "
                   "1.0 %); " + FRONT_CAUSE)
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
