"""The report opens with its verdict (issue 24, point 4), on a copy of the recorded example run.

The summary is the first section and names how the run ended (status.json, or the outcome the
campaign hands over before status.json exists); its stiffness table sets the identified k
beside the finite-element model's own static k and Table 2, with the reason for the k_t/k_b
gap; its stability verdict equals the largest real part of each mode in eig.json, found here
by numpy on the JSON. The rest of the report's promises of point 4: Fig. 8's table has the
variants the bars have, the static c is marked assumed, Pearson values in one precision, the
bag duration to 0.01 s, the timings an appendix at the end.
"""
import json
import re
import shutil

import numpy as np
import pytest
from example_runs import example_reported
from report_html import EXAMPLE, parse_report

from motoflex_ros.plots.labels import VARIANT_LABELS
from motoflex_ros.structures.paper_tables import COMPONENTS, paper_table2_stiffness


@pytest.fixture(scope="module")
def run():
    folder = example_reported()
    return folder, parse_report(folder / "report.html")


def _sections(page):
    return [i for i in page.ids if i.startswith("section-")]


def _row(page, table, first):
    return next(r for r in page.tables[table] if r and r[0][1] == first)


def test_summary_is_first_and_names_the_runs_status(run):
    folder, page = run
    assert _sections(page)[0] == "section-summary"
    status = json.loads((folder / "status.json").read_text())
    assert page.notes["summary-status"].startswith(f"Run {folder.name}: {status['status']}")
    assert "not recorded" not in page.notes["summary-status"]
    eig = json.loads((folder / "eig.json").read_text())
    assert f"lumped '{eig['variant']}' variant" in page.notes["summary-motorcycle"]
    for c in COMPONENTS:
        assert c.replace("_", " ") in page.notes["summary-motorcycle"]


def test_summary_stiffness_against_fe_model_and_table2(run):
    folder, page = run
    identified = json.loads((folder / "identification.json").read_text())
    fe = json.loads((folder / "components.json").read_text())
    paper = paper_table2_stiffness()
    for c in COMPONENTS:
        cells = _row(page, "summary-stiffness", c)
        ours, model, vs_fe, ref, vs_paper = (float(a["data-value"]) for a, _ in cells[1:6])
        assert ours == identified[c]["static"]["k"] and model == fe[c]["k_static"]
        assert vs_fe == pytest.approx((ours / model - 1) * 100, rel=1e-12)
        assert ref == paper[c]["k"]
        assert vs_paper == pytest.approx((ours / ref - 1) * 100, rel=1e-12)
        assert abs(vs_fe) < 1.0          # the bench identifies the structure it tests
        for name, (value, diff) in zip(("k_t", "k_b"), (cells[6:8], cells[8:10])):
            assert float(value[0]["data-value"]) == identified[c][name]
            assert float(diff[0]["data-value"]) == pytest.approx(
                (identified[c][name] / paper[c][name] - 1) * 100, rel=1e-12)
    text = page.sections["section-summary"]
    assert "eq. 12b" in text and "axes" in text and "differ from the paper" in text


def test_summary_stability_verdict_equals_eig_json(run):
    folder, page = run
    eig = json.loads((folder / "eig.json").read_text())
    kmh = np.array(eig["speeds_mps"]) * 3.6
    verdict = page.notes["summary-verdict"]
    for mode in ("weave", "wobble"):
        values = np.array([np.nan if z is None else z[0] for z in eig["modes"][mode]])
        i = int(np.nanargmax(values))
        cells = _row(page, "summary-stability", mode)
        assert float(cells[1][0]["data-value"]) == values[i]
        assert float(cells[2][0]["data-value"]) == pytest.approx(kmh[i])
        stable = bool(np.nanmax(values) < 0)
        assert (cells[4][1] == "stable") == stable
        assert f"{mode} least damped at {kmh[i]:.0f} km/h" in verdict
    everywhere = all(np.nanmax([z[0] for z in eig["modes"][m] if z]) < 0
                     for m in ("weave", "wobble"))
    assert verdict.startswith("Verdict: stable" if everywhere else "Verdict: NOT stable")
    assert f"over {kmh.min():.0f}-{kmh.max():.0f} km/h" in verdict


def test_summary_names_the_outcome_handed_over_before_status_json(tmp_path):
    """The campaign writes the report before status.json: the outcome it hands over is what
    the summary and the provenance say, not 'not recorded'."""
    from motoflex_ros.report.build import build_report
    if not (EXAMPLE / "status.json").is_file():
        pytest.skip("bags/example is not in this checkout")
    folder = tmp_path / "run"
    shutil.copytree(EXAMPLE, folder, ignore=shutil.ignore_patterns(
        "report.html", "*.rrd", "status.json"))
    outcome = {"status": "complete", "reason": None, "time_utc": "2026-12-03T08:00:00Z",
               "source": "motoflex campaign"}
    path, _ = build_report(folder, compute=False, progress=False, outcome=outcome)
    page = parse_report(path)
    assert page.notes["summary-status"] == (
        "Run run: complete (motoflex campaign, 2026-12-03T08:00:00Z).")
    rows = {a["data-path"]: t for a, t in page.cells if a.get("data-kind") == "provenance"}
    assert rows["run status"] == "complete"
    path, _ = build_report(folder, compute=False, progress=False)
    assert "not recorded" in parse_report(path).notes["summary-status"]


def test_report_point4_details(run):
    folder, page = run
    accuracy = json.loads((folder / "accuracy.json").read_text())
    for case, variants in accuracy.items():
        shown = [r[1][1] for r in page.tables["accuracy"][1:] if r[0][1] == case]
        assert shown == [VARIANT_LABELS.get(v, v) for v in variants], case
    statics = [(a, t) for a, t in page.cells if a.get("data-path", "").endswith("static/c")]
    assert len(statics) == 3 and all(t.endswith("(assumed)") for _, t in statics)
    assert "assumed, not identified" in page.sections["section-identification"]
    pearson = [t for a, t in page.cells if "/pearson/" in "/" + a.get("data-path", "")]
    assert len(pearson) == 24 and all(re.fullmatch(r"[+-]\d\.\d{3}", t) for t in pearson)
    duration = next(t for a, t in page.cells if a.get("data-path") == "bag duration [s]")
    assert re.fullmatch(r"\d+\.\d{2}", duration)
    assert _sections(page)[-1] == "section-timings"
    assert page.ids.index("contents") < page.ids.index("section-components")
