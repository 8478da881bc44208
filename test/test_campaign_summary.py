"""What `motoflex campaign` prints at the end (issue 24, point 5), on the example run's results.

The console sets the identified k beside the finite-element model's own static k (computed
here from the shipped component and also in the run's components.json) and Table 2, says in
one sentence why k_t and k_b differ from Table 2, and gives the stability verdict; --json keeps
every result key and adds the bag path and the weave/wobble table with its verdict, which
must equal numpy's largest real part of the modes.
"""
import json
from pathlib import Path

import numpy as np
import pytest

from motoflex_ros.cli.campaign_summary import (
    fe_static_k,
    json_output,
    stiffness_table,
    vehicle_table,
)
from motoflex_ros.launcher.campaign_graph import CampaignOutcome
from motoflex_ros.report.summary import K_SPLIT_REASON
from motoflex_ros.structures.paper_tables import COMPONENTS, paper_table2_stiffness

EXAMPLE = Path(__file__).resolve().parents[1] / "bags" / "example"


def _example(name):
    if not (EXAMPLE / name).is_file():
        pytest.skip("bags/example is not in this checkout")
    return json.loads((EXAMPLE / name).read_text())


def _vehicle_modes():
    """The vehicle_simulator's {mode: {speeds_kmh, real, frequency_hz}} of eig.json's modes."""
    eig = _example("eig.json")
    kmh = [v * 3.6 for v in eig["speeds_mps"]]
    return {m: {"speeds_kmh": kmh,
                "real": [None if z is None else z[0] for z in values],
                "frequency_hz": [None if z is None else z[1] / (2 * np.pi) for z in values]}
            for m, values in eig["modes"].items()}


def test_fe_static_k_is_the_components_own():
    components = _example("components.json")
    fe = fe_static_k(COMPONENTS)
    for c in COMPONENTS:
        assert fe[c] == pytest.approx(components[c]["k_static"], rel=1e-9)


def test_console_shows_identified_against_fe_and_table2_with_the_reason(capsys):
    results = _example("identification.json")
    fe = fe_static_k(COMPONENTS)
    stiffness_table(results, fe)
    out = capsys.readouterr().out
    rows = {(r[0], r[1]): r for r in (line.split() for line in out.splitlines()[2:11])}
    paper = paper_table2_stiffness()
    for c in COMPONENTS:
        k = results[c]["static"]["k"]
        row = rows[(c, "k")]
        assert float(row[2]) == pytest.approx(k, rel=1e-3)
        assert float(row[3]) == pytest.approx(fe[c], rel=1e-3)
        assert row[4] == f"{100 * (k / fe[c] - 1):+.1f}"
        assert row[7] == f"{100 * (k / paper[c]['k'] - 1):+.1f}"
        k_t = rows[(c, "k_t")]
        assert k_t[4] == f"{100 * (results[c]['k_t'] / paper[c]['k_t'] - 1):+.1f}"
    assert K_SPLIT_REASON in out


def test_console_vehicle_verdict(capsys):
    vehicle_table(_vehicle_modes())
    out = capsys.readouterr().out
    assert "stable over 40-210 km/h" in out and "weave least damped at" in out


def test_campaign_json_keeps_results_and_adds_bag_and_stability(tmp_path):
    results = _example("identification.json")
    modes = _vehicle_modes()
    outcome = CampaignOutcome(results, tmp_path / "run", tmp_path / "run" / "x.json", 1.0, 7,
                              modes)
    data = json.loads(json.dumps(json_output(outcome, "static", COMPONENTS)))
    assert set(results) | {"bag", "stability"} == set(data)
    assert all(data[c] == results[c] for c in results)
    assert data["bag"] == str(tmp_path / "run")
    stability = data["stability"]
    assert stability["model"]["variant"] == "static"
    for mode in ("weave", "wobble"):
        assert stability["modes"][mode] == modes[mode]
        real = np.array([np.nan if r is None else r for r in modes[mode]["real"]])
        verdict = stability["verdict"][mode]
        assert verdict["least_damped_real"] == np.nanmax(real)
        assert verdict["least_damped_speed_kmh"] == modes[mode]["speeds_kmh"][
            int(np.nanargmax(real))]
        assert verdict["stable"] == bool(np.nanmax(real) < 0)
    assert stability["stable"] == all(stability["verdict"][m]["stable"]
                                      for m in ("weave", "wobble"))
    bare = CampaignOutcome(results, tmp_path, tmp_path / "x.json", 1.0, 7, {})
    assert json_output(bare, "static", ["swingarm"])["stability"] is None
