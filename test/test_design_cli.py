"""``motoflex study design`` end to end (issue 26), on a small search.

Every reported design is re-evaluated by the full engine (re-reduction at 20 modes / 600 Hz,
the flexible motorcycle built and linearized from scratch): the cheap evaluation must agree to
1e-8 on every index; the lightest feasible design must meet every index floor on the full
engine and be lighter than the nominal. (The Pareto points trade the smallest stability margin
against mass, so their index floors are an objective, not a constraint: their full check must
agree with the cheap one, sign of the margin included.) Its component files, put back with
``motoflex eig --use``, give the same weave and wobble as the design built in memory.
"""
import json

import numpy as np
import pytest

from motoflex_ros.cli.main import main
from motoflex_ros.config import resolve_config
from motoflex_ros.formats.component_file import load_component
from motoflex_ros.formats.design_space_file import load_design_space
from motoflex_ros.report.build import build_report
from motoflex_ros.study.design_space import component_with, design_configs
from motoflex_ros.study.identified_variants import build_variant
from motoflex_ros.vehicle.linearize import linearize
from motoflex_ros.vehicle.model import load_vehicle
from motoflex_ros.vehicle.modes import modal_sweep

INDICES = ("weave_low", "weave_high", "wobble_low", "wobble_high")


@pytest.mark.slow  # a small search, three full checks, the eig round trip: 40 s idle
def test_design_study_end_to_end(tmp_path, capsys):
    out = tmp_path / "designs"
    assert main(["study", "design", "--pop-size", "4", "--generations", "1", "--maxiter", "12",
                 "--max-points", "2", "--seed", "3", "--json", "--out", str(out)]) == 0
    doc = json.loads(capsys.readouterr().out)
    nominal, lightest = doc["nominal"], doc["lightest_feasible"]
    assert set(nominal["indices"]) == set(INDICES)
    assert doc["pareto"] and all(set(p) >= {"mass_kg", "indices", "variables", "full_check"}
                                 for p in doc["pareto"])
    assert lightest is not None, doc["why_none"]
    floors = doc["floors"]
    for point in doc["pareto"] + [lightest]:
        check = point["full_check"]
        assert check["max_abs_difference"] < 1e-8
        cheap_ok = all(point["indices"][n] >= floors[n] - 1e-9 for n in floors)
        assert check["meets_constraints"] == cheap_ok
    assert lightest["mass_kg"] < nominal["mass_kg"]
    assert lightest["full_check"]["meets_constraints"]
    assert all(lightest["full_check"]["indices"][n] >= floors[n] - 1e-9 for n in floors)
    # the report gets a design section from the saved JSON, the lightest design's mass in it
    run = tmp_path / "run"
    run.mkdir()
    (run / "design.json").write_text(json.dumps(doc))
    path, _ = build_report(run, compute=False, progress=False)
    html = path.read_text()
    assert 'id="section-design"' in html and f"{lightest['mass_kg']:.3f}" in html
    assert 'id="design_front"' in html
    # the files round trip: eig --use on them equals the design built in memory
    files = lightest["files"]
    args = ["eig", "--vehicle", "touring", "--speeds-kmh", "60", "150", "--json", "--flex",
            "flexible", "--component", "frame", "--component", "front_assembly",
            "--component", "swingarm"]
    for path in files.values():
        args += ["--use", path]
    assert main(args) == 0
    eig = json.loads(capsys.readouterr().out)
    space = load_design_space("touring")
    x = np.array([lightest["variables"][n] for n in space.names])
    comps = {n: load_component(n) for n in ("frame", "front_assembly", "swingarm")}
    comps.update({c: component_with(cfg, space.sources[c])
                  for c, cfg in design_configs(space, x).items()})
    vehicle = load_vehicle(resolve_config("vehicles", "touring"))
    sweep = modal_sweep(linearize(build_variant(vehicle, "flexible", list(comps), {}, comps)),
                        np.array([60.0, 150.0]) / 3.6)
    for mode in ("weave", "wobble"):
        got = np.array([complex(*pair) for pair in eig["modes"][mode]])
        np.testing.assert_allclose(got, sweep.modes[mode], rtol=1e-9)


def test_report_without_design_study_has_no_design_section(tmp_path):
    path, sections = build_report(tmp_path, compute=False, progress=False)
    assert "design" not in [s.id for s in sections]
    assert 'id="section-design"' not in path.read_text()
