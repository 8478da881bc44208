"""A harmonic test read over a single fitted window has no spread estimate: its 95 % intervals
(and those of everything computed from it: k, J, c of the mode, k_t, k_b) are undefined, NaN in
the core, null in JSON and in the DiagnosticArray, 'n/a' in the tables; never zero width.

The reference is the definition of the interval: with n independent observations the Student t
interval has n - 1 degrees of freedom, none for n = 1. Two windows give a finite, non-zero
interval (one degree of freedom).
"""
import io
import json
import math

import numpy as np
import pytest
import yaml

from motoflex_ros.bench.offline_campaign import only_tests, run_campaign, setup_campaign
from motoflex_ros.cli.identify import _table
from motoflex_ros.cli.output import emit_json
from motoflex_ros.config import config_path
from motoflex_ros.formats.component_file import load_component
from motoflex_ros.formats.json_yaml import to_jsonable, write_results
from motoflex_ros.identify.uncertainty import interval, mean_and_covariance
from motoflex_ros.report.tables import identification_table, table2


def _strict(constant):
    raise ValueError(f"not strict JSON: {constant}")


def campaign(tmp_path, max_periods):
    """The tube's default campaign (static, torsion, bending) with harmonic tests that stop
    after ``max_periods`` (1.5: one fitted window in both; 4: two or more)."""
    data = yaml.safe_load(open(config_path("protocols", "default")))
    data["harmonic"]["max_periods"] = max_periods
    path = tmp_path / f"protocol_{max_periods}.yaml"
    path.write_text(yaml.safe_dump(data))
    setup = only_tests(setup_campaign(load_component("tube"), str(path)),
                       ("static", "torsion", "bending"))
    return run_campaign(setup).identification


@pytest.fixture(scope="module")
def single(tmp_path_factory):
    return campaign(tmp_path_factory.mktemp("single"), 1.5)


def test_interval_of_one_sample_is_undefined_analytic():
    mean, cov = mean_and_covariance(np.array([[1.0, 2.0]]))
    assert np.all(np.isnan(cov))
    assert all(math.isnan(v) for v in interval(mean[0], cov[0, 0]))
    assert all(math.isnan(v) for v in interval(1.0, 0.01, dof=0))
    # one degree of freedom: the Student t quantile 12.706 (two-sided 95 %)
    lo, hi = interval(1.0, 0.01, dof=1)
    assert hi - 1.0 == pytest.approx(12.7062 * 0.1, rel=1e-4) and lo < 1.0


def test_single_window_harmonic_interval_is_undefined_not_zero(single):
    for model in (single.torsion, single.bending):
        assert model.info["n_peaks"] == 2       # one window: its maximum and minimum
        for name in ("l", "beta", "b", "k", "J", "c"):
            assert all(math.isnan(v) for v in model.ci[name]), (name, model.ci[name])
            assert math.isfinite(model.values[name])
    assert all(math.isfinite(v) for v in single.static.ci["k"])   # many samples: defined


def test_two_windows_give_a_finite_nonzero_interval(tmp_path):
    result = campaign(tmp_path, 4)
    for model in (result.torsion, result.bending):
        assert model.info["n_peaks"] >= 4
        lo, hi = model.ci["k"]
        assert math.isfinite(lo) and math.isfinite(hi) and lo < model["k"] < hi


def test_single_window_json_null_roundtrip(single, tmp_path):
    results = {"tube": single.to_dict()}
    out = io.StringIO()
    emit_json(results, out)
    data = json.loads(out.getvalue(), parse_constant=_strict)
    assert data["tube"]["torsion"]["ci"]["k"] == [None, None]
    assert data["tube"]["torsion"]["k"] == pytest.approx(single.torsion["k"], rel=1e-15)
    write_results(tmp_path / "r.json", results)
    assert json.loads((tmp_path / "r.json").read_text(), parse_constant=_strict) == data
    write_results(tmp_path / "r.yaml", results)
    assert yaml.safe_load((tmp_path / "r.yaml").read_text()) == data


def test_single_window_diagnostic_statuses_null_roundtrip(single):
    from motoflex_ros.nodes.result_messages import (
        identification_statuses,
        results_from_statuses,
    )
    statuses = identification_statuses("tube", single.to_dict())
    back = results_from_statuses(statuses)
    back["tube"].setdefault("sweep", [])       # no sweep test ran: no sweep status
    assert back == to_jsonable({"tube": single.to_dict()})
    assert back["tube"]["bending"]["ci"]["J"] == [None, None]


def test_single_window_tables_say_na(single):
    out = io.StringIO()
    _table(to_jsonable({"tube": single.to_dict()}), out)
    rows = {line.split()[1]: line for line in out.getvalue().splitlines()[2:5]}
    assert rows["torsion"].split()[6] == "n/a" and rows["bending"].split()[6] == "n/a"
    assert "[" in rows["static"]
    data = to_jsonable({c: single.to_dict() for c in ("frame", "front_assembly", "swingarm")})
    cells = {cell.path: cell for row in identification_table(data).rows for cell in row
             if cell.path}
    for c in data:
        for bound in (0, 1):
            assert cells[f"{c}/torsion/ci/k/{bound}"].text == "n/a"
            assert cells[f"{c}/torsion/ci/k/{bound}"].value is None
            static = cells[f"{c}/static/ci/k/{bound}"]
            assert static.value == data[c]["static"]["ci"]["k"][bound]
    split_cells = [cell for row in table2(data).rows for cell in row if cell.text == "n/a"]
    assert {c.kind for c in split_cells} == {"json", "diff"}   # tube's k_t, k_b and their diffs
