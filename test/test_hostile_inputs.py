"""Hostile inputs (issue 23, points 4, 5, 12, 14 and 15, and cases of our own).

Each refused case runs the real command (in this process; in a child where it could block:
a FIFO or a device as input) and must exit non-zero within CPU_GUARD_S of CPU time with one
line naming the file and the key (or row and column), without a traceback. Memory is bounded
before work: the CSV reader's peak is measured with tracemalloc on files far above it.
"""
import json
import os
import shutil
import subprocess
import sys
import tracemalloc
from pathlib import Path

import numpy as np
import pytest
from hostile import refused, refused_in_child, write_rig
from measured_cases import bench_yaml
from scipy.io import mmread, mmwrite

from motoflex_ros.cli.main import main
from motoflex_ros.config import config_path
from motoflex_ros.errors import ConfigError, MotoflexError
from motoflex_ros.formats.component_file import load_component
from motoflex_ros.formats.measured_csv import read_csv
from motoflex_ros.formats.superelement_file import export_superelement
from motoflex_ros.identify.measurements import MeasurementError
from motoflex_ros.launcher.status import IncompleteRun, require_complete
from motoflex_ros.report.provenance_section import NOT_RECORDED, provenance_table

EXAMPLE = Path(__file__).resolve().parents[1] / "bags" / "example"


def bomb(levels=9):
    """A YAML flow sequence of nested aliases: 9 levels of 9 stand for 9^9 = 387 million
    strings in about 340 bytes."""
    parts = ['&a0 ["lol", "lol", "lol", "lol", "lol", "lol", "lol", "lol", "lol"]']
    for i in range(1, levels):
        parts.append(f"&a{i} [" + ", ".join([f"*a{i - 1}"] * 9) + "]")
    return "[" + ", ".join(parts) + "]"


def with_bomb(text, key):
    """``text`` with the value of the first line ``key: <value>`` replaced by the bomb."""
    lines = text.splitlines()
    for i, line in enumerate(lines):
        if line.strip().startswith(f"{key}:"):
            lines[i] = line[:line.index(f"{key}:") + len(key) + 1] + " " + bomb()
            return "\n".join(lines) + "\n"
    raise AssertionError(key)


@pytest.fixture(scope="module")
def rig(tmp_path_factory):
    """A measured cantilever record: (folder, its CSV's lines, the bench file)."""
    csv_path, bench = write_rig(tmp_path_factory.mktemp("rig"))
    return csv_path.parent, csv_path.read_text().splitlines(), bench


def measured(csv_path, bench):
    return ["identify", "--measured", csv_path, "--bench", bench]


# --- point 4: the YAML alias bomb, in every kind of configuration file ----------------------

BOMBED = {   # kind: (shipped file, key whose value becomes the bomb, argv with {} for the file)
    "component": (("components", "tube"), "elements", ["components", "--component", "{}"]),
    "protocol": (("protocols", "default"), "force_n",
                 ["identify", "--component", "tube", "--protocol", "{}"]),
    "vehicle": (("vehicles", "touring"), "gravity", ["eig", "--vehicle", "{}", "--speeds-kmh",
                                                "100"]),
}


@pytest.mark.parametrize("kind", [*BOMBED, "bench"])
def test_alias_bomb_is_refused_at_once(tmp_path, capsys, rig, kind):
    """A 600-byte alias bomb hung components, protocol, vehicle and bench files for 60 s or
    more; the message printed the expanded value. Now refused before any value is built."""
    path = tmp_path / f"{kind}.yaml"
    if kind == "bench":
        path.write_text(with_bomb(rig[2].read_text(), "loaded_end"))
        argv = measured(rig[0] / "rig.csv", path)
    else:
        (folder, name), key, argv = BOMBED[kind]
        path.write_text(with_bomb(config_path(folder, name).read_text(), key))
        argv = [str(path) if a == "{}" else a for a in argv]
    err = refused(argv, capsys, path, "aliases", "above the limit of 100,000")
    assert "lol" not in err and len(err) < 400


def test_alias_bomb_in_a_node_parameters_file(tmp_path):
    """A node's --params-file goes through the same loader (a process: a node, in a private
    ROS domain and log folder)."""
    from motoflex_ros.launcher.domain import DomainLock
    from motoflex_ros.launcher.graph import ros_env
    path = tmp_path / "params.yaml"
    path.write_text(f"vehicle_simulator:\n  ros__parameters:\n    vehicle: {bomb()}\n")
    with DomainLock() as lock:
        err = refused_in_child(["--ros-args", "--params-file", path], path, "aliases",
                               module="motoflex_ros.nodes.vehicle_simulator",
                               env=ros_env(lock.domain_id, tmp_path / "ros_log"))
    assert "lol" not in err


def test_alias_loop_is_refused(tmp_path, capsys):
    path = tmp_path / "loop.yaml"
    path.write_text(config_path("components", "tube").read_text().replace(
        "pitch_deg: 0.0", "pitch_deg: &s [1, *s]"))
    refused(["components", "--component", path], capsys, path, "contains itself", "line 3")


def test_messages_quote_values_cut_short(tmp_path, capsys):
    """A wrong value of 50,000 items (no alias) is quoted with a few of them only."""
    path = tmp_path / "long.yaml"
    path.write_text(config_path("components", "tube").read_text().replace(
        "pitch_deg: 0.0", "pitch_deg: [" + ", ".join(["12345"] * 50_000) + "]"))
    err = refused(["components", "--component", path], capsys, path, "tube.pitch_deg",
                  "12345, 12345")
    assert len(err) < 300


# --- point 5: a measured CSV is counted while it is read -------------------------------------

def _many_rows(path, lines, n):
    """A CSV of ``n`` rows: the record's header and one row repeated with increasing t."""
    row = lines[5].split(",", 1)[1]
    with open(path, "w") as stream:
        stream.write(lines[0] + "\n")
        stream.writelines(f"{i * 1e-3!r},{row}\n" for i in range(n))
    return path


def test_rows_are_refused_at_the_limit_while_streaming(tmp_path, capsys, rig, monkeypatch):
    """10 million rows took 94 s and 5.2 GB before "above the limit". The rows are counted as
    they are read: refused at the first row past the limit, whatever follows; the reader's
    peak memory is a small fraction of the file."""
    folder, lines, bench = rig
    path = _many_rows(tmp_path / "many.csv", lines, 100_000)
    monkeypatch.setenv("MOTOFLEX_LIMIT_SAMPLES", "1000")
    refused(measured(path, bench), capsys, path, "stopped at row 1,001", "limit of 1,000")
    tracemalloc.start()
    with pytest.raises(ConfigError):
        read_csv(path)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    assert peak < 0.05 * path.stat().st_size, (peak, path.stat().st_size)


def test_huge_sparse_file_is_refused_at_its_first_line(tmp_path, capsys, rig):
    """A 1.9 GB sparse file (no line end, NUL bytes) took 4 GB: refused at line 1."""
    path = tmp_path / "sparse.csv"
    with open(path, "wb") as stream:
        stream.truncate(1_900_000_000)
    refused(measured(path, rig[2]), capsys, path, "line 1")
    tracemalloc.start()
    with pytest.raises(MeasurementError):
        read_csv(path)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    assert peak < 20e6


# --- point 12: tracebacks that become one line ------------------------------------------------

@pytest.fixture(scope="module")
def superelement(tmp_path_factory):
    """The tube exported as a superelement: (folder, K, M)."""
    folder = tmp_path_factory.mktemp("superelement")
    export_superelement(load_component("tube"), folder)
    return folder, np.asarray(mmread(str(folder / "tube_K.mtx"))), \
        np.asarray(mmread(str(folder / "tube_M.mtx")))


def _singular(m):
    m = m.copy()
    m[-1, :] = m[:, -1] = 0.0
    return m


def _indefinite(m):
    m = m.copy()
    m[8, 8] = -abs(m).max()
    return m


SUPERELEMENT_CASES = {   # name: (K of K, M -> matrix, which file, words)
    "M negated": (lambda k, m: (k, -m), "mass", ["not positive definite"]),
    "M zero": (lambda k, m: (k, 0 * m), "mass", ["largest |entry| 0"]),
    "M singular": (lambda k, m: (k, _singular(m)), "mass", ["not positive definite"]),
    "M indefinite": (lambda k, m: (k, _indefinite(m)), "mass", ["not positive definite"]),
    "K negated": (lambda k, m: (-k, m), "stiffness", ["clamps' rows deleted",
                                                      "not positive definite"]),
    "K times 1e-300": (lambda k, m: (k * 1e-300, m), "stiffness", ["largest |entry|"]),
    "K times 1e290": (lambda k, m: (k * 1e290, m), "stiffness", ["largest |entry|"]),
}


@pytest.mark.parametrize("case", sorted(SUPERELEMENT_CASES))
def test_bad_superelement_matrices(tmp_path, capsys, superelement, case):
    """LinAlgError, ZeroDivisionError or ArpackError before: now the file and key."""
    folder, k, m = superelement
    edit, which, words = SUPERELEMENT_CASES[case]
    shutil.copytree(folder, tmp_path / "se")
    k, m = edit(k, m)
    for name, matrix in (("K", k), ("M", m)):
        mmwrite(str(tmp_path / "se" / f"tube_{name}.mtx"), matrix, precision=17)
    yaml_path = tmp_path / "se" / "tube.yaml"
    refused(["components", "--component", yaml_path, "--json"], capsys, yaml_path,
            f"superelement.{which}", f"tube_{'K' if which == 'stiffness' else 'M'}.mtx",
            *words)


@pytest.mark.parametrize("layout", ["array", "coordinate"])
def test_truncated_matrix_files(tmp_path, capsys, superelement, layout):
    """A truncated array-format .mtx was padded with zeros (point 15); a truncated coordinate
    one: either is refused naming the file and how many entries it lacks."""
    folder, _, m = superelement
    shutil.copytree(folder, tmp_path / "se")
    path = tmp_path / "se" / "tube_M.mtx"
    if layout == "coordinate":
        from scipy.sparse import coo_matrix
        mmwrite(str(path), coo_matrix(m), precision=17)
    text = path.read_text().splitlines()
    path.write_text("\n".join(text[:len(text) - 5]) + "\n")
    yaml_path = tmp_path / "se" / "tube.yaml"
    refused(["components", "--component", yaml_path, "--json"], capsys, yaml_path,
            "superelement.mass", "tube_M.mtx", "truncated")


def test_matrix_header_too_large_is_refused_before_reading(tmp_path, capsys, superelement):
    """A header claiming 10^9 rows: refused from the header, nothing allocated."""
    folder, _, _ = superelement
    shutil.copytree(folder, tmp_path / "se")
    path = tmp_path / "se" / "tube_K.mtx"
    path.write_text("%%MatrixMarket matrix array real general\n1000000000 1000000000\n1.0\n")
    refused(["components", "--component", tmp_path / "se" / "tube.yaml"], capsys,
            "superelement.stiffness", "1000000000 coordinates, more than 20000")


def test_csv_with_a_byte_order_mark_is_read(tmp_path, rig):
    """A CSV saved with a UTF-8 BOM (Excel) gave KeyError 't': now read as without it."""
    folder, lines, _ = rig
    path = tmp_path / "bom.csv"
    path.write_bytes(b"\xef\xbb\xbf" + "\r\n".join(lines).encode() + b"\r\n")
    plain, with_bom = read_csv(folder / "rig.csv"), read_csv(path)
    np.testing.assert_array_equal(with_bom.t, plain.t)
    np.testing.assert_array_equal(with_bom.markers, plain.markers)
    np.testing.assert_array_equal(with_bom.wrench, plain.wrench)


@pytest.mark.parametrize("record", [{}, "no git fields", {"sensor_noise_m": [1, 2],
                                                         "git_commit": ["x"], "seed": {}}],
                         ids=["empty", "no git fields", "wrong types"])
def test_provenance_without_fields_is_reported_as_not_recorded(tmp_path, record):
    """provenance.json without git fields, or {}, gave AttributeError in the report (a
    missing reason where the HTML expects text)."""
    if record == "no git fields":
        record = json.loads((EXAMPLE / "provenance.json").read_text())
        for key in ("git_commit", "git_dirty", "git_note"):
            del record[key]
    (tmp_path / "provenance.json").write_text(json.dumps(record))
    table = provenance_table(tmp_path)
    for row in table.rows:
        assert all(isinstance(cell.text, str) for cell in row), row
    values = {row[0].text: row[1].text for row in table.rows}
    assert values["git commit"] == NOT_RECORDED
    if "command" not in record:
        assert values["sensor noise [m]"] == NOT_RECORDED


@pytest.mark.parametrize("metadata", ["rosbag2_bagfile_information: {duration: [1]}\n",
                                      "rosbag2_bagfile_information: " + bomb() + "\n"],
                         ids=["missing keys", "alias bomb"])
def test_bad_bag_metadata_in_the_report(tmp_path, metadata):
    """The report's provenance reads the bag's metadata.yaml: a malformed or bombed one is
    'not recorded', with why, not a KeyError or a hang."""
    (tmp_path / "metadata.yaml").write_text(metadata)
    rows = {row[0].text: row for row in provenance_table(tmp_path).rows}
    assert rows["messages in the bag"][1].text == NOT_RECORDED
    assert "metadata.yaml unreadable" in rows["messages in the bag"][2].text


def test_status_nested_100k_deep(tmp_path, capsys):
    """A status.json nested 100,000 deep gave RecursionError: now 'unreadable', named."""
    shutil.copy(EXAMPLE / "metadata.yaml", tmp_path)
    (tmp_path / "status.json").write_text("[" * 100_000 + "]" * 100_000)
    with pytest.raises(IncompleteRun, match="status.json: nested too deeply"):
        require_complete(tmp_path)
    refused(["report", tmp_path, "--no-compute"], capsys, tmp_path, "status.json",
            "nested too deeply")


def _result(**change):
    ci = {"l": [0.19, 0.2], "beta": [1.56, 1.58], "b": [0.40, 0.41], "k": [2.0e4, 2.1e4],
          "c": [20.0, 21.0], "level": 0.95}
    static = {"l": 0.195, "beta": 1.57, "b": 0.405, "k": 2.05e4, "c": 20.5, "ci": ci}
    result = {"static": static, "torsion": None, "bending": None, "k_t": None, "k_b": None,
              "ci": {"k_t": [None, None], "k_b": [None, None], "level": 0.95}}
    for path, value in change.items():
        node = result
        keys = path.split("__")
        for key in keys[:-1]:
            node = node[key]
        node[keys[-1]] = value
    return {"tube": result}


COMPARE_CASES = {   # name: (change of the second file, key named)
    "a list for a model": ({"static": [1, 2]}, "tube.static"),
    "a list for ci": ({"static__ci": [1, 2]}, "tube.static.ci"),
    "a short ci": ({"static__ci__k": [2.0e4]}, "tube.static.ci.k"),
    "text for a value": ({"static__k": "stiff"}, "tube.static.k"),
    "a list for the eq. 12 ci": ({"ci": [0]}, "tube.ci"),
}


@pytest.mark.parametrize("case", sorted(COMPARE_CASES))
def test_compare_with_results_of_the_wrong_shape(tmp_path, capsys, case):
    """`compare` with a list where a mapping belongs, or a short ci: AttributeError and
    IndexError before."""
    change, key = COMPARE_CASES[case]
    a, b = tmp_path / "a.json", tmp_path / "b.json"
    a.write_text(json.dumps(_result()))
    b.write_text(json.dumps(_result(**change)))
    assert main(["compare", str(a), str(a), "--json"]) == 0
    capsys.readouterr()
    refused(["compare", a, b], capsys, b, f"key '{key}'")


# --- point 14: a FIFO where a bag's MCAP file belongs ----------------------------------------

@pytest.mark.parametrize("target", ["folder", "file"])
def test_bag_info_on_a_fifo_does_not_block(tmp_path, target):
    bag = tmp_path / "bag"
    bag.mkdir()
    shutil.copy(EXAMPLE / "metadata.yaml", bag)
    os.mkfifo(bag / "bag_0.mcap")
    refused_in_child(["bag", "info", bag if target == "folder" else bag / "bag_0.mcap"],
                     "bag_0.mcap", "FIFO", "not a regular file")


# --- point 15 -------------------------------------------------------------------------------

def test_times_shifted_by_1e12_s_are_refused(tmp_path, capsys, rig):
    """Times of 1e12 s keep 0.1 ms: the decay tests were dropped silently. Refused, saying
    what to do."""
    _, lines, bench = rig
    path = tmp_path / "shifted.csv"
    path.write_text("\n".join([lines[0]] + [f"{float(line.split(',', 1)[0]) + 1e12!r},"
                                            f"{line.split(',', 1)[1]}" for line in lines[1:]]))
    refused(measured(path, bench), capsys, path, "column 't'", "subtract the first time")


def test_times_of_the_unix_epoch_are_kept(tmp_path, rig):
    """Times as a real rig stamps them (seconds since 1970, 1.7e9 s: 0.24 us steps) at 1 kHz
    are read: the resolution check refuses only what loses the sampling interval."""
    _, lines, _ = rig
    path = tmp_path / "epoch.csv"
    path.write_text("\n".join([lines[0]] + [f"{float(line.split(',', 1)[0]) + 1.7e9!r},"
                                            f"{line.split(',', 1)[1]}" for line in lines[1:]]))
    assert len(read_csv(path).t) == len(lines) - 1


def test_values_are_printed_with_their_digits(tmp_path, capsys):
    """Poisson's ratio 0.49999999 was reported as "value 0.5" against the limit 0.499."""
    from motoflex_ros.formats.mesh_examples import write_bracket_component
    path = write_bracket_component(tmp_path, size=0.05)
    path.write_text(path.read_text().replace("nu: 0.33", "nu: 0.49999999"))
    err = refused(["components", "--component", path], capsys, path, "material.nu",
                  "value 0.49999999", "0.499]")
    assert "value 0.5 " not in err


def test_failed_replay_keeps_its_logs_beside_its_output(tmp_path, capsys, monkeypatch):
    """A failed `replay --identify OUT` left its node logs in ~/.ros/log: now beside OUT,
    and the message names them there."""
    from motoflex_ros.cli.replay import replay_logs
    from motoflex_ros.launcher import run

    def failing_graph(specs, pacer, duration_s, work_dir=None, **kw):
        (work_dir / "log").mkdir(parents=True, exist_ok=True)
        (work_dir / "log" / "identification.log").write_text("the node's last words\n")
        raise MotoflexError(f"node identification failed; its log: "
                            f"{work_dir / 'log' / 'identification.log'}")
    monkeypatch.setattr(run, "run_graph", failing_graph)
    monkeypatch.setenv("ROS_LOG_DIR", str(tmp_path / "ros_log"))
    out = tmp_path / "out" / "id.json"
    kept = replay_logs(out) / "log" / "identification.log"
    refused(["replay", EXAMPLE, "--identify", out], capsys, kept)
    assert kept.read_text() == "the node's last words\n"
    assert not (tmp_path / "ros_log").exists() and not out.exists()


def test_real_failed_replay_keeps_its_logs_beside_its_output(tmp_path):
    """The same with the real graph (a process: ROS nodes, in a free domain): a bag of the
    example's phase messages and clock only, marked complete, cannot be identified; the run
    fails and its node logs are beside the output, none in the ROS log folder."""
    from motoflex_ros.launcher.status import write_status
    from motoflex_ros.record.mcap_bag import BagWriter, bag_info, read_messages
    keep = [t for t in bag_info(EXAMPLE).topics if t.name.endswith("/phase") or
            t.name == "/clock"]
    with BagWriter(tmp_path / "bag") as bag:
        for topic in keep:
            bag.add_topic(topic.name, topic.type)
        for message in read_messages(EXAMPLE, [t.name for t in keep]):
            bag.write(message.topic, message.log_time_ns, message.data)
    write_status(tmp_path / "bag", "complete")
    out = tmp_path / "out" / "id.json"
    env = {k: v for k, v in os.environ.items() if k != "ROS_DOMAIN_ID"}   # a free one
    env["ROS_LOG_DIR"] = str(tmp_path / "ros_log")
    run = subprocess.run([sys.executable, "-m", "motoflex_ros.cli.main", "replay",
                          str(tmp_path / "bag"), "--identify", str(out)], env=env,
                         capture_output=True, text=True, timeout=600)
    assert run.returncode == 2 and "Traceback" not in run.stderr, run.stderr
    kept = tmp_path / "out" / "id_replay" / "log"
    assert str(kept) in run.stderr
    assert {"bag_replay.log", "identification.log"} <= {p.name for p in kept.iterdir()}
    assert not out.exists()
    assert not any((tmp_path / "ros_log").rglob("*.log"))


# --- own cases: hostile files of every kind ---------------------------------------------------

def _tube_text(old, new):
    text = config_path("components", "tube").read_text()
    assert old in text
    return text.replace(old, new, 1)


def _csv_text(lines, edit):
    return edit(lines)


OWN_CASES = {
    # name: (file name, content: str/bytes or a function of the CSV lines, argv kind, words)
    "CSV in UTF-16": ("rig.csv", lambda lines: "\n".join(lines).encode("utf-16"),
                      "measured", ["not a text CSV file"]),
    "CSV with a NUL byte": ("rig.csv", lambda lines: "\n".join(lines[:50] + ["\0"] +
                                                                 lines[50:]),
                            "measured", ["line 51", "NUL"]),
    "CSV header of 1.2 million characters": (
        "rig.csv", lambda lines: ",".join(["t"] * 600_000) + "\n", "measured",
        ["line 1", "longer than 1,000,000 characters"]),
    "CSV of 2,000 markers": (
        "rig.csv", lambda lines: "t,test,fx,fy,fz,mx,my,mz," + ",".join(
            f"m{i}_{a}" for i in range(1, 2001) for a in "xyz") + "\n", "measured",
        ["header", "2,000 markers", "at most 1,000"]),
    "YAML with a NUL byte": ("tube.yaml", _tube_text("tube: {", "tube: {\0"), "component",
                             ["#x0000"]),
    "YAML nested 1,300 deep": (
        "tube.yaml", "".join(" " * i + "k:\n" for i in range(1300)) + " " * 1300 + "1\n",
        "component", ["nesting depth", "line 1000"]),
    "NaN for a float": ("tube.yaml", _tube_text("length: 0.6", "length: .nan"), "component",
                        ["tube.length", "finite"]),
    "inf for a whole number": ("tube.yaml", _tube_text("elements: 20", "elements: .inf"),
                               "component", ["'elements'", "finite"]),
    "-inf in a protocol": ("protocol.yaml", config_path("protocols", "default").read_text()
                           .replace("force_n: 100.0", "force_n: -.inf"), "protocol",
                           ["static.force_n", "finite"]),
    "NaN in a vector": ("bench.yaml", bench_yaml("rig", [float("nan"), 0.0, 0.0], "from_data")
                        .replace("nan", ".nan"), "bench", ["loaded_end[0]", "finite"]),
    "inf for the vehicle's gravity": ("vehicle.yaml", config_path("vehicles", "touring")
                                      .read_text().replace("gravity: 9.81", "gravity: .inf", 1),
                                      "vehicle", ["'gravity'", "finite"]),
    "binary results for compare": ("b.json", bytes(range(256)) * 4, "compare",
                                   ["not a text YAML file"]),
    "results nested 100,000 deep": ("b.json", "[" * 100_000 + "]" * 100_000, "compare",
                                    ["nesting depth"]),
    "a directory as the component file": ("tube.yaml", None, "component",
                                          ["is a directory, not a regular file"]),
    "a directory as the measured CSV": ("rig.csv", None, "measured",
                                        ["not a readable rosbag2 folder"]),
    "a symlink loop as the component file": ("tube.yaml", "loop", "component",
                                             ["symbolic links"]),
}


def _argv(kind, path, rig_files):
    folder, _, bench = rig_files
    return {"measured": measured(path, bench),
            "component": ["components", "--component", path],
            "protocol": ["identify", "--component", "tube", "--protocol", path],
            "bench": measured(folder / "rig.csv", path),
            "vehicle": ["eig", "--vehicle", path, "--speeds-kmh", "100"],
            "compare": ["compare", path, path]}[kind]


@pytest.mark.parametrize("case", sorted(OWN_CASES))
def test_own_hostile_files(tmp_path, capsys, rig, case):
    name, content, kind, words = OWN_CASES[case]
    path = tmp_path / name
    if callable(content):
        content = content(list(rig[1]))
    if content is None:
        path.mkdir()
    elif content == "loop":
        path.symlink_to(path)
    elif isinstance(content, bytes):
        path.write_bytes(content)
    else:
        path.write_text(content)
    refused(_argv(kind, path, rig), capsys, path, *words)


@pytest.mark.parametrize("kind", ["FIFO as the component file", "FIFO as the measured CSV",
                                  "/dev/zero as the component file",
                                  "FIFO as a superelement matrix", "FIFO as a mesh file"])
def test_inputs_that_would_block(tmp_path, rig, superelement, kind):
    """Read in a child: a FIFO or a device opened for reading would block or never end."""
    if kind.endswith("mesh file"):
        from motoflex_ros.formats.mesh_examples import write_bracket_component
        path = write_bracket_component(tmp_path, size=0.05)
        (tmp_path / "bracket.msh").unlink()
        os.mkfifo(tmp_path / "bracket.msh")
        refused_in_child(["components", "--component", path], path, "mesh.file",
                         "bracket.msh", "FIFO")
        return
    if kind.startswith("/dev/zero"):
        refused_in_child(["components", "--component", "/dev/zero"], "/dev/zero",
                         "character device")
        return
    if kind.endswith("matrix"):
        shutil.copytree(superelement[0], tmp_path / "se")
        (tmp_path / "se" / "tube_M.mtx").unlink()
        os.mkfifo(tmp_path / "se" / "tube_M.mtx")
        refused_in_child(["components", "--component", tmp_path / "se" / "tube.yaml"],
                         "tube_M.mtx", "superelement.mass", "FIFO")
        return
    path = tmp_path / ("tube.yaml" if "component" in kind else "rig.csv")
    os.mkfifo(path)
    argv = _argv("component" if "component" in kind else "measured", path, rig)
    refused_in_child(argv, path, "FIFO")
