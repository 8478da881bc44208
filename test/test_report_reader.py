"""The report as a chassis engineer reads it (issue 16, point 7), on the recorded example run.

bags/example is copied to a temporary folder (nothing in bags/ is written) with a
provenance.json of another command and seed (its own inputs and bag kept), and `motoflex
report` is run on the copy. The HTML is parsed back: ids unique, provenance equal to the run's
status.json, metadata.yaml and provenance.json (and 'not recorded' where the run has no
record), the identified motorcycle named in the stability section, deviations from Table 2
beyond the stated threshold flagged, no timing rows of zeros, no figure wider than the page,
beta in degrees. The figures themselves are checked on their matplotlib objects: distinct axis
styles, no text overlapping or cut off, every Fig. 8 bar visible, mode shapes scaled as stated.
"""
import json
from collections import Counter

import numpy as np
import pytest
import yaml
from report_html import EXAMPLE, example_report, parse_report, png_size

from motoflex_ros.launcher.campaign_graph import VEHICLE_VARIANT
from motoflex_ros.launcher.provenance import utc_stamp, write_provenance
from motoflex_ros.report.html import CONTENT_WIDTH_PX
from motoflex_ros.report.tables import DEVIATION_FLAG_PERCENT
from motoflex_ros.structures.paper_tables import COMPONENTS, paper_table2_stiffness

ARGV = ["campaign", "--out", "bags/example", "--seed", "3", "--noise", "2e-05"]
MAX_DOWNSCALE = 1.0
"""A figure may be at most this many times the page's content width: shown 1:1, not shrunk."""


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    def with_provenance(folder):   # the run's own inputs and bag, another command and seed
        recorded = json.loads((folder / "provenance.json").read_text())
        write_provenance(folder, ARGV, list(COMPONENTS), 3, 2e-5, None, 1_796_168_200.0,
                         recorded["inputs"], folder / recorded["bag"]["file"])
    folder = example_report(tmp_path_factory.mktemp("runs"), with_provenance)
    return folder, parse_report(folder / "report.html")


def _provenance(page):
    return {attrs["data-path"]: (attrs["data-kind"], text)
            for attrs, text in page.cells if attrs.get("data-kind") in ("provenance", "missing")}


def test_report_ids_are_unique(run):
    _, page = run
    twice = [i for i, n in Counter(page.ids).items() if n > 1]
    assert twice == [] and len(page.ids) > 20


def test_report_provenance_equals_the_runs_records(run):
    folder, page = run
    fields = _provenance(page)
    status = json.loads((folder / "status.json").read_text())
    bag = yaml.safe_load((folder / "metadata.yaml").read_text())["rosbag2_bagfile_information"]
    record = json.loads((folder / "provenance.json").read_text())
    expected = {
        "run status": status["status"], "run ended (UTC)": status["time_utc"],
        "bag start (UTC)": utc_stamp(bag["starting_time"]["nanoseconds_since_epoch"] / 1e9),
        "bag duration [s]": f"{bag['duration']['nanoseconds'] / 1e9:.2f}",
        "messages in the bag": str(bag["message_count"]), "ROS distribution": bag["ros_distro"],
        "command": "motoflex " + " ".join(ARGV), "seed": "3",
        "run started (UTC)": "2026-12-01T23:36:40Z",
        "motoflex_ros version": record["package_version"],
        "sensor noise [m]": ", ".join(f"{c} 2e-05" for c in COMPONENTS)}
    for field, value in expected.items():
        assert fields[field] == ("provenance", value), field
    commit = record["git_commit"]
    if commit is None:
        assert fields["git commit"] == ("missing", "not recorded")
    else:
        assert fields["git commit"][1].startswith(commit)


def test_report_provenance_says_what_a_run_does_not_record(tmp_path):
    """A run folder without provenance.json (runs older than it): every field it would give is
    'not recorded', the others still come from status.json and metadata.yaml."""
    import shutil

    from motoflex_ros.report.provenance_section import NOT_RECORDED, provenance_table
    if not (EXAMPLE / "status.json").is_file():
        pytest.skip("bags/example is not in this checkout")
    old = tmp_path / "example"
    shutil.copytree(EXAMPLE, old, ignore=shutil.ignore_patterns("*.rrd", "report.html",
                                                                "provenance.json"))
    rows = {r[0].text: r for r in provenance_table(old).rows}
    for field in ("command", "seed", "sensor noise [m]", "git commit", "motoflex_ros version"):
        value, source = rows[field][1], rows[field][2]
        assert (value.kind, value.text) == ("missing", NOT_RECORDED)
        assert "no provenance.json" in source.text
    assert rows["run status"][1].text == json.loads((old / "status.json").read_text())[
        "status"]


def test_report_stability_section_names_the_identified_motorcycle(run):
    folder, page = run
    eig = json.loads((folder / "eig.json").read_text())
    assert eig["variant"] == VEHICLE_VARIANT
    text = page.sections["section-vehicle"]
    assert f"lumped '{eig['variant']}' variant of {', '.join(eig['components'])}" in text
    assert "identification.json" in page.notes["vehicle-model"]
    assert "rigid" not in text


def test_report_flags_deviations_beyond_the_threshold(run):
    folder, page = run
    diffs = [(a, t) for a, t in page.cells if a.get("data-kind") == "diff"]
    assert len(diffs) == 15 + 12       # Tables 1 and 2, and the summary's
    for attrs, text in diffs:
        beyond = abs(float(attrs["data-value"])) > DEVIATION_FLAG_PERCENT
        assert (attrs.get("class") == "flag") == beyond, (attrs, text)
        assert ("\u26a0" in text) == beyond
    # the deviations the issue names: k_t of the frame +158 %, of the swingarm -78 %
    identified = json.loads((folder / "identification.json").read_text())
    paper = paper_table2_stiffness()
    flagged = {a["data-path"] for a, _ in diffs if a.get("class") == "flag"}
    for c in ("frame", "swingarm"):
        assert abs(identified[c]["k_t"] / paper[c]["k_t"] - 1) > 0.5
        assert f"table2/{c}/k_t" in flagged
    assert f"\u00b1{DEVIATION_FLAG_PERCENT:g} %" in page.sections["section-identification"]


def test_report_timings_have_no_rows_of_zeros(run):
    _, page = run
    rows = page.tables["timings"][1:]
    assert len(rows) >= 3
    for (_, step), (_, seconds) in rows:
        assert float(seconds) > 0.0, step
    assert any("further steps" in step for (_, step), _ in rows)


def test_report_figures_are_not_shrunk(run):
    _, page = run
    assert f"max-width: {CONTENT_WIDTH_PX}px" in page.css
    assert len(page.figures) == 10
    for name, png in page.figures.items():
        width, _ = png_size(png)
        assert width <= MAX_DOWNSCALE * CONTENT_WIDTH_PX, (name, width)


def test_report_beta_in_degrees_and_defined(run):
    folder, page = run
    angles = [(a, t) for a, t in page.cells if a.get("data-shown-unit") == "deg"]
    identified = json.loads((folder / "identification.json").read_text())
    hinges = sum(len(r["principal"]["hinges"]) for r in identified.values()
                 if r["principal"]["identified"])
    assert hinges == 5   # frame 1 (its metric has one direction), front assembly 2, swingarm 2
    assert len(angles) == 3 * len(COMPONENTS) + hinges   # static, torsion, bending + hinges
    for attrs, text in angles:
        assert attrs["data-path"].endswith("/beta")
        assert float(text) == pytest.approx(np.degrees(float(attrs["data-value"])), abs=0.006)
    section = page.sections["section-identification"]
    assert "\u03b2 [deg]" in section and "angle from the line O-q0" in section


def test_report_mode_figures_state_their_scale(run):
    from motoflex_ros.plots.component_figure import MODE_FRACTION
    _, page = run
    for c in COMPONENTS:
        caption = page.captions[f"modes_{c}"]
        assert "scale factor" in caption and f"{MODE_FRACTION:.0%}" in caption


def test_report_axes_figures_are_the_identify_plot(run):
    """One figure code: the report's Figs. 5-7 are the PNGs of plots.axes.axes_figure."""
    from motoflex_ros.plots.axes import axes_figure
    from motoflex_ros.report.figures import component_model, png_of
    folder, page = run
    identified = json.loads((folder / "identification.json").read_text())
    for number, c in zip((5, 6, 7), COMPONENTS):
        drawn = png_of(axes_figure(component_model(c)[0], identified[c]))
        assert page.figures[f"fig{number}_{c}"] == drawn, c
