"""``motoflex study sensitivity`` on the decomposed lumped touring motorcycle.

The identification input is made from the components' finite-element models directly (torsion
and bending mode axes) with the paper's Table 2 stiffnesses, so the test does not depend on the
bench. The verb's indices are checked run by run against an independent path: the vehicle
engine's own linearization and modal sweep (QZ + MAC) of that run's motorcycle.
"""
import json
from pathlib import Path

import numpy as np
import pytest
import yaml

from motoflex_ros.cli.main import main
from motoflex_ros.config import MOTORCYCLE_COMPONENTS, config_path
from motoflex_ros.formats.component_file import load_component
from motoflex_ros.study.factorial import FACTORS, PAPER_TABLE2_NOMINAL, full_factorial
from motoflex_ros.study.identified_variants import build_variant
from motoflex_ros.study.motorcycle import with_stiffness
from motoflex_ros.study.stability_index import stability_index
from motoflex_ros.vehicle.linearize import linearize
from motoflex_ros.vehicle.model import load_vehicle
from motoflex_ros.vehicle.modes import modal_sweep

COMPONENTS = MOTORCYCLE_COMPONENTS


@pytest.fixture(scope="module")
def identified_file(tmp_path_factory):
    identified = {}
    for name in COMPONENTS:
        reduced = load_component(name).clamped_reduced()
        identified[name] = {test: {"l": float(reduced.mode_axis(test).l),
                                   "beta": float(reduced.mode_axis(test).beta)}
                            for test in ("torsion", "bending")}
    identified = with_stiffness(identified, PAPER_TABLE2_NOMINAL)
    path = tmp_path_factory.mktemp("study") / "identified.yaml"
    path.write_text(yaml.safe_dump(identified))
    return path


@pytest.fixture(scope="module")
def sensitivity(identified_file, tmp_path_factory):
    plots = tmp_path_factory.mktemp("plots")
    import contextlib
    import io

    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        code = main(["study", "sensitivity", "--identified", str(identified_file),
                     "--step-kmh", "2", "--json", "--plot", str(plots)])
    assert code == 0
    return json.loads(out.getvalue()), plots


@pytest.mark.slow
def test_sensitivity_json_shape(sensitivity):
    data, plots = sensitivity
    assert set(data) == {"nominal", "indices", "anova_main_share", "pearson"}
    assert data["nominal"] == pytest.approx(PAPER_TABLE2_NOMINAL, rel=1e-12)
    names = {"weave_low", "weave_high", "wobble_low", "wobble_high"}
    assert set(data["indices"]) == names and set(data["pearson"]) == names
    assert all(len(values) == 64 for values in data["indices"].values())
    for name in names:
        assert 0.0 <= data["anova_main_share"][name] <= 1.0
        assert set(data["pearson"][name]) == set(FACTORS)
        assert all(-1.0 <= rho <= 1.0 for rho in data["pearson"][name].values())
    assert (plots / "fig10_pearson.png").stat().st_size > 10_000


@pytest.mark.slow
@pytest.mark.parametrize("run", [0, 37, 63])
def test_sensitivity_indices_equal_engine_modal_sweep(sensitivity, identified_file, run):
    data, _ = sensitivity
    design = full_factorial(PAPER_TABLE2_NOMINAL, levels=2)
    values = {f: design.physical[run, i] for i, f in enumerate(design.factors)}
    identified = with_stiffness(yaml.safe_load(identified_file.read_text()), values)
    components = {name: load_component(name) for name in COMPONENTS}
    model = build_variant(load_vehicle(config_path("vehicles", "touring")), "decomposed",
                          list(COMPONENTS), identified, components)
    speeds = np.arange(40.0, 210.0 + 1e-9, 2.0) / 3.6
    sweep = modal_sweep(linearize(model), speeds)
    for mode in ("weave", "wobble"):
        for name in ("low", "high"):
            index = stability_index(speeds, sweep.real_part(mode)[None], name)
            assert data["indices"][f"{mode}_{name}"][run] == pytest.approx(index.s[0],
                                                                           rel=1e-8)


def test_negative_identified_stiffness_is_named(identified_file, tmp_path, capsys):
    data = yaml.safe_load(identified_file.read_text())
    data["frame"]["k_b"] = -2.65e6
    bad = tmp_path / "bad.yaml"
    bad.write_text(yaml.safe_dump(data))
    assert main(["study", "sensitivity", "--identified", str(bad)]) == 2
    assert "frame.k_b" in capsys.readouterr().err


@pytest.mark.parametrize("verb", [["study", "accuracy"],
                                  ["eig", "--vehicle", "touring", "--speeds-ms", "20",
                                   "--flex", "static", "--component", "swingarm"]])
def test_bad_identified_value_names_the_file(verb, tmp_path, capsys):
    """The message names the file the user gave, the dotted key and the allowed range."""
    example = Path(__file__).resolve().parents[1] / "bags" / "example" / "identification.json"
    data = yaml.safe_load(example.read_text())
    data["swingarm"]["static"]["k"] = -5.0
    bad = tmp_path / "bad.yaml"
    bad.write_text(yaml.safe_dump(data))
    assert main([*verb, "--identified", str(bad)]) == 2
    err = capsys.readouterr().err
    assert f"{bad}: key 'swingarm.static.k'" in err and "(> 0)" in err


@pytest.mark.parametrize(("argv", "key"), [(["--levels", "1"], "levels"),
                                           (["--range-rel", "1.5"], "range"),
                                           (["--step-kmh", "0"], "--step-kmh")])
def test_bad_arguments_are_named(argv, key, capsys):
    assert main(["study", "sensitivity", "--identified", "missing.yaml"] + argv) == 2
    assert key in capsys.readouterr().err
