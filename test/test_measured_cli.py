"""``motoflex identify --measured FILE --bench BENCH.yaml`` (issue 17): the result shape of
``motoflex identify``, no finite-element model loaded, and bad measured input refused in one
line naming the file, the row and the column (or the bench file's key)."""
import json
import subprocess
import sys

import numpy as np
import pytest
from measured_cases import PLATE, bench_yaml, cantilever_record, hinge_record, verb_script

from motoflex_ros.cli.main import main
from motoflex_ros.formats.measured_csv import write_csv


@pytest.fixture()
def hinge_files(tmp_path):
    t, wrench, points, truth, q0 = hinge_record(noise_m=5e-6)
    write_csv(tmp_path / "hinge.csv", t, wrench, points)
    (tmp_path / "bench.yaml").write_text(bench_yaml("hinge", q0, "from_data"))
    return tmp_path / "hinge.csv", tmp_path / "bench.yaml", truth


def test_measured_cli_needs_no_structures(hinge_files, tmp_path):
    """The verb's measured path runs with the structures package (the FE model) and the
    virtual bench's campaign blocked (an import of them fails), and gives the results' shape
    and values. (The ``motoflex`` parser itself imports every verb, the eigenvalue verb the
    vehicle and its structures; the verb is registered alone here.)"""
    csv_path, bench_path, truth = hinge_files
    out = tmp_path / "out.json"
    script = verb_script(["--measured", csv_path, "--bench", bench_path, "--json", "--out",
                          out], blocked=("motoflex_ros.structures",
                                         "motoflex_ros.bench.offline_campaign",
                                         "motoflex_ros.bench.response", "motoflex_ros.bench.plan"))
    run = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    printed = json.loads(run.stdout)
    assert printed == json.loads(out.read_text())
    result = printed["hinge"]
    assert set(result) >= {"static", "torsion", "bending", "k_t", "k_b", "split_identifiable",
                           "split_problem", "ci", "sweep", "modal", "measured"}
    assert result["torsion"] is None and result["k_t"] is None
    assert result["bending"]["k"] == pytest.approx(truth["k"], rel=0.01)
    assert result["bending"]["J"] == pytest.approx(truth["J"], rel=0.01)


def test_measured_cli_table_and_plot(hinge_files, tmp_path, capsys):
    csv_path, bench_path, _ = hinge_files
    assert main(["identify", "--measured", str(csv_path), "--bench", str(bench_path),
                 "--plot", str(tmp_path / "plots")]) == 0
    text = capsys.readouterr().out
    assert "hinge" in text and "torsion" in text and "n/a" in text
    assert "decay" in text and "marker frames" in text
    assert (tmp_path / "plots" / "hinge_axes.png").stat().st_size > 1000


# --- bad input ----------------------------------------------------------------------------

def _cantilever_csv(path, **change):
    t, wrench, points, _, q0 = cantilever_record(noise_m=5e-6)
    write_csv(path, t, wrench, points)
    return q0


def _rewrite(path, edit):
    lines = path.read_text().splitlines()
    path.write_text("\n".join(edit(lines)) + "\n")


def _edit_cell(row, column):
    def edit(lines):
        header = lines[0].split(",")
        cells = lines[row].split(",")
        cells[header.index(column)] = "nan"
        lines[row] = ",".join(cells)
        return lines
    return edit


def _drop_column(name):
    def edit(lines):
        k = lines[0].split(",").index(name)
        return [",".join(c for i, c in enumerate(line.split(",")) if i != k) for line in lines]
    return edit


def _keep_markers(n):
    def edit(lines):
        return [",".join(line.split(",")[:8 + 3 * n]) for line in lines]
    return edit


def _swap_times(lines):
    a, b = lines[40].split(","), lines[41].split(",")
    a[0], b[0] = b[0], a[0]
    lines[40], lines[41] = ",".join(a), ",".join(b)
    return lines


def _no_load(lines):
    header = lines[0].split(",")
    k = header.index("fy")
    rng = np.random.default_rng(0)
    out = [lines[0]]
    for line in lines[1:]:
        cells = line.split(",")
        cells[k] = repr(float(0.01 * rng.standard_normal()))
        out.append(",".join(cells))
    return out


def _collinear(lines):
    """Every marker on the x axis through the tip: a line."""
    header = lines[0].split(",")
    out = [lines[0]]
    for line in lines[1:]:
        cells = line.split(",")
        for i in range(1, 5):
            cells[header.index(f"m{i}_y")] = cells[header.index("m1_y")]
            cells[header.index(f"m{i}_z")] = cells[header.index("m1_z")]
        out.append(",".join(cells))
    return out


def _reserved_label(lines):
    for i in range(300, 310):
        cells = lines[i].split(",")
        cells[1] = "modal"
        lines[i] = ",".join(cells)
    return lines


CSV_CASES = {
    "test label that is a result key": (_reserved_label, "from_data",
                                        ["row 300 (line 301)", "column 'test'", "'modal'"]),
    # name: (edit of the CSV, bench markers, words the message must hold)
    "missing column": (_drop_column("fy"), "from_data", ["header", "column 'fy'", "missing"]),
    "time not increasing": (_swap_times, "from_data", ["row 41 (line 42)", "column 't'",
                                                       "increase"]),
    "NaN in a row": (_edit_cell(17, "m2_y"), "from_data", ["row 17 (line 18)",
                                                           "column 'm2_y'", "finite"]),
    "fewer than 3 markers": (_keep_markers(2), "from_data", ["header", "column 'm3_x'",
                                                              "at least 3"]),
    "collinear markers": (_collinear, "from_data", ["m1_x..m4_z", "collinear",
                                                    ">= 0.001 m"]),
    "load never exceeds the noise": (_no_load, "from_data", ["column 'fy'", "never exceeds",
                                                             "noise"]),
    "markers do not fit the offsets": (lambda lines: lines, [[0.1, 0, 0], [0, 0.1, 0],
                                                             [0, 0, 0.1], [0.1, 0.1, 0]],
                                       ["rigid", "residual", "marker order"]),
}


@pytest.mark.parametrize("case", sorted(CSV_CASES))
def test_bad_measured_csv(tmp_path, capsys, case):
    edit, markers, words = CSV_CASES[case]
    csv_path = tmp_path / "rig.csv"
    q0 = _cantilever_csv(csv_path)
    _rewrite(csv_path, edit)
    (tmp_path / "bench.yaml").write_text(bench_yaml("rig", q0, markers))
    out = tmp_path / "out.json"
    code = main(["identify", "--measured", str(csv_path), "--bench",
                 str(tmp_path / "bench.yaml"), "--out", str(out)])
    err = capsys.readouterr().err.strip()
    assert code == 2
    assert len(err.splitlines()) == 1, err
    assert str(csv_path) in err, err
    for word in words:
        assert word in err, (word, err)
    assert not out.exists()


BENCH_CASES = {
    "unknown key": ("bench: rig\nloaded_end: [0.6, 0, 0]\nmarkers: from_data\nmarker: 1\n"
                    "sensor: {noise_m: 5.0e-6, latency_s: 0.0}\n",
                    ["key 'marker'", "unknown key", "allowed keys"]),
    "missing key": ("bench: rig\nmarkers: from_data\nsensor: {noise_m: 5.0e-6, "
                    "latency_s: 0.0}\n", ["key 'loaded_end'", "missing"]),
    "noise out of range": ("bench: rig\nloaded_end: [0.6, 0, 0]\nmarkers: from_data\n"
                           "sensor: {noise_m: 0.5, latency_s: 0.0}\n",
                           ["key 'sensor.noise_m'", "[0, 0.001]"]),
    "two markers": ("bench: rig\nloaded_end: [0.6, 0, 0]\nmarkers: [[0.1, 0, 0], [0, 0.1, "
                    "0]]\nsensor: {noise_m: 5.0e-6, latency_s: 0.0}\n",
                    ["key 'markers'", "at least 3"]),
    "collinear offsets": ("bench: rig\nloaded_end: [0.6, 0, 0]\nmarkers: [[0.1, 0, 0], "
                          "[0.2, 0, 0], [0.3, 0, 0]]\nsensor: {noise_m: 5.0e-6, latency_s: "
                          "0.0}\n", ["key 'markers'", "collinear"]),
    "loaded end at the clamp": ("bench: rig\nloaded_end: [0, 0.3, 0]\nmarkers: from_data\n"
                                "sensor: {noise_m: 5.0e-6, latency_s: 0.0}\n",
                                ["key 'loaded_end'", ">= 0.001 m"]),
    "bad name": ("bench: my rig\nloaded_end: [0.6, 0, 0]\nmarkers: from_data\n"
                 "sensor: {noise_m: 5.0e-6, latency_s: 0.0}\n", ["key 'bench'", "a letter"]),
}


@pytest.mark.parametrize("case", sorted(BENCH_CASES))
def test_bad_bench_file(tmp_path, capsys, case):
    text, words = BENCH_CASES[case]
    csv_path = tmp_path / "rig.csv"
    _cantilever_csv(csv_path)
    (tmp_path / "bench.yaml").write_text(text)
    code = main(["identify", "--measured", str(csv_path), "--bench",
                 str(tmp_path / "bench.yaml")])
    err = capsys.readouterr().err.strip()
    assert code == 2 and len(err.splitlines()) == 1, err
    assert str(tmp_path / "bench.yaml") in err
    for word in words:
        assert word in err, (word, err)


def test_measured_needs_a_bench_file_and_no_model_options(tmp_path, capsys):
    csv_path = tmp_path / "rig.csv"
    q0 = _cantilever_csv(csv_path)
    assert main(["identify", "--measured", str(csv_path)]) == 2
    assert "--bench" in capsys.readouterr().err
    (tmp_path / "bench.yaml").write_text(bench_yaml("rig", q0, PLATE))
    assert main(["identify", "--measured", str(csv_path), "--bench",
                 str(tmp_path / "bench.yaml"), "--component", "frame"]) == 2
    assert "'--component'" in capsys.readouterr().err
