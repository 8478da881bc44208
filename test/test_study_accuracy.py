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


@pytest.mark.xfail(strict=True, reason="ours: alike on wobble (f 6.7 vs 6.2 %, Re 38.1 vs 39.1 %) "
                   "but not on the weave real part (2.8 vs 1.5 %) once the state-of-the-art "
                   "stiffness is measured, as the paper says, with a lateral force at the axle")
def test_published_state_of_the_art_and_bending_alike_for_front_assembly(verb_run):
    """Sect. 5.2.2: for the front assembly the state-of-the-art and the bending models give
    very similar results (the bending axis is almost perpendicular to the fork)."""
    front = verb_run[0]["front_assembly"]
    for quantity in QUANTITIES:
        a, b = front["state_of_the_art"][quantity], front["bending"][quantity]
        assert abs(a - b) <= 0.25 * max(a, b) + 0.5, (quantity, a, b)


@pytest.mark.xfail(strict=True, reason="ours: state_of_the_art is best for the frame (wobble Re "
                   "~5 % vs static ~13 %) and no variant beats ~37 % on the front assembly's "
                   "wobble real part; see the issue note")
def test_published_static_lowest_error_in_every_case(verb_run):
    """Sect. 5.2: the static model has the lowest e_RMS in each of the four cases."""
    table = verb_run[0]
    for case in CASES:
        totals = {v: sum(table[case][v].values()) for v in ACCURACY_VARIANTS}
        assert min(totals, key=totals.get) == "static", (case, totals)


@pytest.mark.xfail(strict=True, reason="ours: ~40 % with all components flexible, set by the "
                   "front assembly (see the issue note)")
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
