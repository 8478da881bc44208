"""`motoflex report RUN`: every table and figure is there, and every number equals its JSON.

The run folder holds JSON documents in the shapes the verbs promise (issues 4-7; the numbers
are drawn from a seeded generator, since only their round trip is checked here). The report is
parsed back and every number cell is compared with the value at its path in its JSON file;
paper values with the paper's tables; differences recomputed.
"""
import base64
import json
from html.parser import HTMLParser
from pathlib import Path

import numpy as np
import pytest
from hostile import run_motoflex

from motoflex_ros.report.published import meijaard2007_eigenvalues
from motoflex_ros.report.tables import VARIANTS
from motoflex_ros.structures.paper_tables import (
    COMPONENTS,
    paper_table1_eigenfrequencies,
    paper_table2_stiffness,
)
from motoflex_ros.study.accuracy import QUANTITIES
from motoflex_ros.study.factorial import FACTORS
from motoflex_ros.study.stability_index import INDEX_NAMES

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"
EXAMPLE = Path(__file__).resolve().parents[1] / "bags" / "example"


def _documents(rng):
    def num(low, high):
        return float(rng.uniform(low, high))

    components = {c: {"f_torsion_hz": num(20, 300), "f_bending_hz": num(50, 300),
                      "k_static": num(1e4, 1e6), "dofs": 500, "modes": 20} for c in COMPONENTS}

    def test_values():
        return {"l": num(-0.5, 0.5), "beta": num(0, 3.1), "b": num(0.1, 0.6), "k": num(1e4, 1e6),
                "J": num(0.1, 2), "c": num(1, 100), "f_hz": num(20, 300)}

    identify = {c: {"static": {k: num(0.1, 1e6) if k == "k" else num(0.05, 0.6)
                               for k in ("l", "beta", "b", "k", "c")},
                    "torsion": test_values(), "bending": test_values(), "k_t": num(1e4, 1e6),
                    "k_b": num(1e4, 1e6),
                    "sweep": [{"f_hz": f, "l": num(-0.3, 0.3), "beta": num(0.2, 2.9),
                               "b": num(0.1, 0.5)} for f in (1.0, 5.0, 10.0)]}
                for c in COMPONENTS}
    accuracy = {case: {v: {q: num(0, 20) for q in QUANTITIES} for v in VARIANTS}
                for case in (*COMPONENTS, "all")}
    sensitivity = {"nominal": {f: num(1e4, 1e6) for f in FACTORS},
                   "indices": {i: [num(-3, -0.1) for _ in range(64)] for i in INDEX_NAMES},
                   "anova_main_share": {i: num(0.9, 1.0) for i in INDEX_NAMES},
                   "pearson": {i: {f: num(-1, 1) for f in FACTORS} for i in INDEX_NAMES}}
    whipple = {"speeds_mps": [5.0, 10.0], "eigenvalues": [
        [[z.real + num(-1e-9, 1e-9), z.imag] for z in (*ref.values(), ref["weave"].conjugate())]
        for ref in meijaard2007_eigenvalues().values()]}
    speeds = [v / 3.6 for v in range(40, 211, 10)]

    def eig(variant, components):
        modes = {m: [[num(-3, -0.1), num(6, 60)] for _ in speeds] for m in ("weave", "wobble")}
        return {"vehicle": "touring", "variant": variant, "components": components,
                "speeds_mps": speeds, "eigenvalues": [[[num(-5, 0), num(0, 60)]] for _ in speeds],
                "modes": modes}
    docs = {"components.json": components, "identify.json": identify,
            "accuracy.json": accuracy, "sensitivity.json": sensitivity,
            "whipple.json": whipple, "eig.json": eig("static", list(COMPONENTS)),
            "timings.json": {"identify": 12.5}}
    for variant in ("flexible", "state_of_the_art", "static"):
        docs[f"eig_front_assembly_{variant}.json"] = eig(variant, ["front_assembly"])
    return docs


class _Cells(HTMLParser):
    """Collect number cells (attributes), figure images and captions by id."""

    def __init__(self):
        super().__init__()
        self.cells, self.figures, self.missing, self.captions = [], {}, [], {}
        self._figure = self._tag = None

    def handle_starttag(self, tag, attrs):
        attrs = dict(attrs)
        if tag == "td" and "data-value" in attrs:
            self.cells.append(attrs)
        if tag == "figure":
            self._figure = attrs["id"]
        if tag == "img" and self._figure:
            self.figures[self._figure] = attrs["src"]
        if tag == "p" and "data-missing" in attrs:
            self.missing.append(attrs["data-missing"])
        self._tag = tag

    def handle_data(self, data):
        if self._tag == "figcaption" and self._figure:
            self.captions[self._figure] = self.captions.get(self._figure, "") + data


def _report(folder, *extra):
    result = run_motoflex(["report", folder, "--no-compute", *extra])
    assert result.returncode == 0, result.stderr
    parser = _Cells()
    parser.feed((folder / "report.html").read_text(encoding="utf-8"))
    return parser, result


@pytest.fixture(scope="module")
def full_report(tmp_path_factory):
    folder = tmp_path_factory.mktemp("bags") / "run7"
    folder.mkdir()
    docs = _documents(np.random.default_rng(7))
    for name, doc in docs.items():
        (folder / name).write_text(json.dumps(doc), encoding="utf-8")
    parser, result = _report(folder)
    return docs, parser, result


def _at(doc, path):
    for key in path.split("/"):
        doc = doc[int(key)] if isinstance(doc, list) else doc[key]
    return doc


def _paper(path):
    table, *keys = path.split("/")
    if table == "table1":
        return paper_table1_eigenfrequencies()[keys[0]][keys[1]]
    if table == "table2":
        return paper_table2_stiffness()[keys[0]][keys[1]]
    z = meijaard2007_eigenvalues()[float(keys[0])][keys[1]]
    return z.real if keys[2] == "re" else z.imag


def test_report_numbers_roundtrip_json(full_report):
    docs, parser, _ = full_report
    json_cells = [c for c in parser.cells if c.get("data-kind") == "json"]
    assert len(json_cells) > 150
    for cell in json_cells:
        assert float(cell["data-value"]) == _at(docs[cell["data-json"]], cell["data-path"]), cell
    for cell in parser.cells:
        if cell.get("data-kind") == "paper":
            assert float(cell["data-value"]) == _paper(cell["data-path"]), cell


def test_report_tables_are_complete(full_report):
    docs, parser, _ = full_report
    paths = {(c.get("data-json"), c["data-path"]) for c in parser.cells if "data-path" in c}
    for c in COMPONENTS:
        for shape in ("torsion", "bending"):
            assert ("components.json", f"{c}/f_{shape}_hz") in paths
        for key in ("static/k", "k_t", "k_b"):
            assert ("identify.json", f"{c}/{key}") in paths
    for i in INDEX_NAMES:
        for f in FACTORS:
            assert ("sensitivity.json", f"pearson/{i}/{f}") in paths
    for case in (*COMPONENTS, "all"):
        for v in VARIANTS:
            for q in QUANTITIES:
                assert ("accuracy.json", f"{case}/{v}/{q}") in paths
    assert ("timings.json", "identify") in paths


def test_report_differences_against_paper(full_report):
    docs, parser, _ = full_report
    diffs = {c["data-path"]: float(c["data-value"]) for c in parser.cells
             if c.get("data-kind") == "diff"}
    assert len(diffs) == 6 + 9 + 12     # Tables 1, 2 and the summary's k, k_t, k_b, vs FE
    for c in COMPONENTS:
        ours = docs["components.json"][c]["f_torsion_hz"]
        paper = paper_table1_eigenfrequencies()[c]["torsion"]
        assert diffs[f"table1/{c}/torsion"] == pytest.approx((ours - paper) / paper * 100,
                                                              rel=1e-12)
        ours = docs["identify.json"][c]["k_b"]
        paper = paper_table2_stiffness()[c]["k_b"]
        assert diffs[f"table2/{c}/k_b"] == pytest.approx((ours - paper) / paper * 100, rel=1e-12)


def test_report_whipple_check_published(full_report):
    _, parser, _ = full_report
    gaps = [float(c["data-value"]) for c in parser.cells if c.get("data-kind") == "absdiff"]
    assert len(gaps) == 6
    assert max(gaps) < 1e-6


def test_report_has_every_figure_as_inline_png(full_report):
    _, parser, _ = full_report
    expected = {"fig5_frame", "fig6_front_assembly", "fig7_swingarm", "fig8", "fig9", "fig10",
                "modes_frame", "modes_front_assembly", "modes_swingarm", "eig_touring"}
    assert expected <= set(parser.figures)
    for src in parser.figures.values():
        assert src.startswith("data:image/png;base64,")
        assert base64.b64decode(src.split(",", 1)[1])[:8] == PNG_MAGIC
    assert parser.missing == []


def test_report_lists_missing_sections_not_invented(tmp_path):
    folder = tmp_path / "run8"
    folder.mkdir()
    docs = _documents(np.random.default_rng(8))
    (folder / "components.json").write_text(json.dumps(docs["components.json"]))
    parser, result = _report(folder, "--quiet")
    assert "Identification (Table 2)" in parser.missing
    assert "Sensitivity (Fig. 10)" in parser.missing
    assert "Components and their modes (Table 1)" not in parser.missing
    assert "not available" in result.stdout
    assert all(c.get("data-json") in (None, "components.json") for c in parser.cells)


def test_report_not_a_run_folder_is_a_clear_error(tmp_path):
    result = run_motoflex(["report", tmp_path / "missing"])
    assert result.returncode == 2
    assert "not a run folder" in result.stderr
    assert not (tmp_path / "missing").exists()


def test_report_reads_campaign_identification_json(tmp_path):
    folder = tmp_path / "run9"
    folder.mkdir()
    identify = _documents(np.random.default_rng(9))["identify.json"]
    (folder / "identification.json").write_text(json.dumps(identify))
    parser, _ = _report(folder, "--quiet")
    cells = [c for c in parser.cells if c.get("data-kind") == "json"]
    assert {c["data-json"] for c in cells} == {"identification.json"}
    for cell in cells:
        assert float(cell["data-value"]) == _at(identify, cell["data-path"])
    assert ("identification.json", "frame/k_t") in {(c["data-json"], c["data-path"])
                                                    for c in cells}


def test_report_passes_the_runs_identification_to_the_verbs(tmp_path):
    from motoflex_ros.report.sources import IDENTIFIED, _arguments
    args = ("study", "accuracy", "--identified", IDENTIFIED)
    assert _arguments(tmp_path, args) == ["study", "accuracy"]
    (tmp_path / "identification.json").write_text("{}")
    assert _arguments(tmp_path, args) == ["study", "accuracy", "--identified",
                                          str(tmp_path / "identification.json")]


def test_report_vehicle_stability_names_the_variant(full_report):
    """Issue 16, point 7: the section said 'rigid' whatever eig.json held; it names the model
    eig.json records, or says that it records none."""
    from motoflex_ros.report.build import _vehicle
    assert full_report[1].captions["eig_touring"] == (
        "Touring motorcycle, lumped 'static' variant of frame, front_assembly, swingarm: weave "
        "and wobble against speed")
    legacy = {k: v for k, v in full_report[0]["eig.json"].items()
              if k not in ("vehicle", "variant", "components")}
    note, figure = _vehicle({"eig": legacy}, {"eig": "eig.json", "identify": "identify.json"})
    assert "model not recorded in eig.json" in figure.caption and "rigid" not in figure.caption
    assert "does not record which motorcycle" in note.text


def test_report_vehicle_source_is_the_campaigns_motorcycle(tmp_path):
    """The report's eig.json is the motorcycle the campaign prints: the vehicle_simulator's
    variant of the run's identified values, equal to the core's sweep of that model."""
    from motoflex_ros.cli.inputs import identification_results, motorcycle_components
    from motoflex_ros.config import resolve_config
    from motoflex_ros.launcher.campaign_graph import campaign_specs
    from motoflex_ros.report.sources import SOURCES, RunData, _load_one
    from motoflex_ros.study.identified_variants import build_variant
    from motoflex_ros.vehicle.linearize import linearize
    from motoflex_ros.vehicle.model import load_vehicle
    from motoflex_ros.vehicle.modes import modal_sweep
    if not (EXAMPLE / "identification.json").is_file():
        pytest.skip("bags/example is not in this checkout")
    (vehicle,) = [s.params for s in campaign_specs(COMPONENTS, tmp_path / "bag")
                  if s.name == "vehicle_simulator"]
    (tmp_path / "identification.json").write_text((EXAMPLE / "identification.json").read_text())
    run = RunData()
    _load_one(tmp_path, next(s for s in SOURCES if s.name == "eig"), True, run)
    eig = run.data["eig"]
    assert (eig["vehicle"], eig["variant"], eig["components"]) == (
        "touring", vehicle["variant"], vehicle["components"])
    names = vehicle["components"]
    model = build_variant(load_vehicle(resolve_config("vehicles", "touring")), eig["variant"],
                          names, identification_results(tmp_path / "identification.json",
                                                        names), motorcycle_components(names))
    sweep = modal_sweep(linearize(model), np.array(eig["speeds_mps"]))
    for mode in ("weave", "wobble"):
        got = np.array([complex(*z) for z in eig["modes"][mode]])
        np.testing.assert_allclose(got, sweep.modes[mode], rtol=1e-12)
