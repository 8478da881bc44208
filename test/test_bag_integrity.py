"""Bags verified before use, reports only of what the run recorded (issue 23, points 6, 7, 8),
and hostile bags and run folders of our own.

Every case runs the ``motoflex`` command as a user would (in this process, but ``replay``,
which starts ROS nodes) and checks: exit code 2 within
FAULT_S, one line on stderr naming what is wrong and where (file, chunk, byte offset), no
traceback, nothing written in place of what was there. The bags are small synthetic ones
(many 2 kB chunks) or a copy of bags/example, doctored.
"""
import json
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

import pytest
from hostile import run_motoflex

from motoflex_ros.cli.main import build_parser
from motoflex_ros.input_pins import sha256_file
from motoflex_ros.launcher.status import write_status
from motoflex_ros.record import mcap_bag

EXAMPLE = Path(__file__).resolve().parents[1] / "bags" / "example"
FAULT_S = 10.0
MESSAGES = 400


@pytest.fixture(scope="module", autouse=True)
def verbs_imported():
    """The CLI's verb modules imported before the first timed command (a child process
    imported them inside FAULT_S on every call; in this process only the first would)."""
    build_parser()


def _cli(*argv, cwd=None):
    """(the command's result, its wall time [s]); ``replay`` (ROS nodes for --identify) in a
    process of its own, the other verbs in this one (hostile.run_motoflex)."""
    start = time.monotonic()
    if argv[0] != "replay":
        return run_motoflex(argv, cwd=cwd), time.monotonic() - start
    done = subprocess.run([sys.executable, "-m", "motoflex_ros.cli.main", *map(str, argv)],
                          capture_output=True, text=True, timeout=120, cwd=cwd,
                          env=dict(os.environ, ROS_LOG_DIR=str(Path(cwd or ".") / "roslog")))
    return done, time.monotonic() - start


def _refused(done, seconds, *words):
    """Exit 2 within FAULT_S, the last stderr line names every one of ``words``, no
    traceback; returns that line."""
    assert done.returncode == 2, (done.returncode, done.stderr)
    assert seconds < FAULT_S, seconds
    assert "Traceback" not in done.stderr, done.stderr
    line = done.stderr.strip().splitlines()[-1]
    for word in words:
        assert str(word) in line, (word, line)
    return line


def _bag(path, n=MESSAGES):
    """A finished bag of ``n`` String-sized messages in many small chunks."""
    with mcap_bag.BagWriter(path, chunk_size=2048) as writer:
        writer.add_topic("/clock", "rosgraph_msgs/msg/Clock")
        for k in range(n):
            writer.write("/clock", 10**9 + 10**6 * k, bytes(4) + k.to_bytes(4, "little") +
                         bytes(4))
    return path


def _chunk_offsets(mcap_file):
    from mcap.reader import make_reader
    with open(mcap_file, "rb") as stream:
        summary = make_reader(stream).get_summary()
    return sorted(c.chunk_start_offset for c in summary.chunk_indexes)


def _flip(mcap_file, offset, bit=0x10):
    data = bytearray(mcap_file.read_bytes())
    data[offset] ^= bit
    mcap_file.write_bytes(bytes(data))


def _corrupt_middle_chunk(bag):
    """Flip one bit inside the data of the middle chunk; returns that chunk's (number, byte
    offset)."""
    mcap_file = mcap_bag.find_mcap(bag)
    offsets = _chunk_offsets(mcap_file)
    number = len(offsets) // 2
    _flip(mcap_file, offsets[number] + 80)   # past the chunk's header: its compressed data
    return number + 1, offsets[number]


# ---------------------------------------------------------------- point 6: CRC on every read
def test_flipped_bit_fails_every_read_naming_chunk_and_offset(tmp_path):
    bag = _bag(tmp_path / "run")
    clean = [m.data for m in mcap_bag.read_messages(bag)]
    assert len(clean) == MESSAGES
    number, offset = _corrupt_middle_chunk(bag)
    where = (f"chunk {number} of", f"at byte offset {offset}")
    with pytest.raises(mcap_bag.BagError, match=f"chunk {number} of .* at byte offset {offset}"):
        list(mcap_bag.read_messages(bag))
    with pytest.raises(mcap_bag.BagError, match="is corrupt"):
        mcap_bag.bag_info(bag, verify=True)
    _refused(*_cli("bag", "info", bag, cwd=tmp_path), *where)
    out = tmp_path / "identified.json"
    _refused(*_cli("replay", bag, "--identify", out, cwd=tmp_path), *where)
    assert not out.exists()


def test_corrupt_summary_section_is_named(tmp_path):
    bag = _bag(tmp_path / "run")
    mcap_file = mcap_bag.find_mcap(bag)
    _flip(mcap_file, mcap_file.stat().st_size - 60)   # inside the summary, before the footer
    _refused(*_cli("bag", "info", bag, cwd=tmp_path), mcap_file, "summary section",
             "is corrupt")


# ---------------------------------------------------------------- point 7: repair
def test_repair_of_a_finished_bag_writes_a_new_marked_bag(tmp_path):
    """A finished bag with one corrupt chunk: the original is never touched; the salvage (all
    other chunks) goes to <bag>_repaired, marked, and says what it lost."""
    bag = _bag(tmp_path / "run")
    number, offset = _corrupt_middle_chunk(bag)
    before = sha256_file(mcap_bag.find_mcap(bag))
    done, seconds = _cli("bag", "repair", bag, "--json", cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    assert sha256_file(mcap_bag.find_mcap(bag)) == before   # not in place
    summary = json.loads(done.stdout)
    repaired = tmp_path / "run_repaired"
    assert summary["path"] == str(repaired)
    assert f"chunk at byte offset {offset} corrupt" in summary["repaired"]
    kept = [m.data for m in mcap_bag.read_messages(repaired)]   # every CRC of the new bag holds
    assert MESSAGES // 2 < len(kept) < MESSAGES and summary["message_count"] == len(kept)
    info = mcap_bag.bag_info(repaired, verify=True)
    assert info.repaired.startswith(f"salvaged {len(kept)} messages from {bag}")
    shown, _ = _cli("bag", "info", repaired, cwd=tmp_path)
    assert shown.returncode == 0 and "REPAIRED BAG (not as recorded)" in shown.stdout
    # a second repair does not overwrite the first one's bag
    _refused(*_cli("bag", "repair", bag, cwd=tmp_path), repaired, "exists")
    # replay refuses it as a run that did not finish, and with --allow-incomplete says what
    # it is; report refuses it, and with --allow-incomplete labels it at the top
    _refused(*_cli("replay", repaired, "--identify", tmp_path / "x.json", cwd=tmp_path),
             "did not finish")
    done, _ = _cli("replay", repaired, "--allow-incomplete", "--identify", tmp_path / "x.json",
                   cwd=tmp_path)
    assert f"warning: {repaired} is a repaired bag, not as recorded: salvaged" in done.stderr
    _refused(*_cli("report", repaired, "--no-compute", "--quiet", cwd=tmp_path),
             "did not finish")
    done, _ = _cli("report", repaired, "--no-compute", "--quiet", "--allow-incomplete",
                   cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    html = (repaired / "report.html").read_text()
    top = html.index('<p class="warning" id="warning">Incomplete run: ')
    assert "its bag was repaired" in html[top:top + 1000] and top < html.index("<section")


def test_repair_of_a_killed_recorders_bag_stays_in_place_and_is_marked(tmp_path):
    bag = _bag(tmp_path / "run")
    mcap_file = mcap_bag.find_mcap(bag)
    with open(mcap_file, "r+b") as stream:   # the footer and summary never written
        stream.truncate(_chunk_offsets(mcap_file)[-1] + 30)
    (bag / mcap_bag.METADATA_FILE).unlink()
    _refused(*_cli("bag", "info", bag, cwd=tmp_path), bag, "bag repair")
    done, _ = _cli("bag", "repair", bag, cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    assert "REPAIRED BAG" in done.stdout and not (tmp_path / "run_repaired").exists()
    info = mcap_bag.bag_info(bag, verify=True)
    assert 0 < info.message_count < MESSAGES and "incomplete record" in info.repaired


# ---------------------------------------------------------------- hostile bags of our own
@pytest.mark.parametrize("damage", ["truncated footer", "zero length", "wrong magic",
                                    "inserted duplicate chunk", "garbage tail"])
def test_damaged_bags_are_refused_with_one_line(tmp_path, damage):
    bag = _bag(tmp_path / "run")
    mcap_file = mcap_bag.find_mcap(bag)
    data = mcap_file.read_bytes()
    offsets = _chunk_offsets(mcap_file)
    doctored = {"truncated footer": data[:-20],
                "zero length": b"",
                "wrong magic": b"\x89MCAQ" + data[5:],
                "inserted duplicate chunk": data[:offsets[2]] + data[offsets[1]:offsets[2]] +
                data[offsets[2]:],
                "garbage tail": data + b"\x00garbage" * 10}[damage]
    mcap_file.write_bytes(doctored)
    _refused(*_cli("bag", "info", bag, cwd=tmp_path), mcap_file)
    out = tmp_path / "out.json"
    _refused(*_cli("replay", bag, "--identify", out, cwd=tmp_path), mcap_file)
    assert not out.exists() and mcap_file.read_bytes() == doctored


def test_lost_chunk_is_a_count_mismatch_not_silence(tmp_path, monkeypatch):
    """A chunk the summary indexes twice (or not at all) is found by the message count."""
    bag = _bag(tmp_path / "run")
    original = mcap_bag._open_summary

    def doubled(mcap_file):
        summary, repaired = original(mcap_file)
        summary.chunk_indexes.append(summary.chunk_indexes[0])
        return summary, repaired
    monkeypatch.setattr(mcap_bag, "_open_summary", doubled)
    with pytest.raises(mcap_bag.BagError, match=f"its summary counts {MESSAGES}"):
        list(mcap_bag.read_messages(bag))


# ---------------------------------------------------------------- point 8: report
@pytest.fixture()
def run(tmp_path):
    """A copy of bags/example as the campaign now leaves it (provenance with the bag's hash)."""
    if not (EXAMPLE / "metadata.yaml").is_file():
        pytest.skip("bags/example is not in this checkout")
    folder = tmp_path / "example"
    shutil.copytree(EXAMPLE, folder, ignore=shutil.ignore_patterns("*.rrd", "report.html"))
    made = json.loads((folder / "provenance.json").read_text())
    made["bag"] = {"file": "example_0.mcap", "sha256": sha256_file(folder / "example_0.mcap")}
    (folder / "provenance.json").write_text(json.dumps(made))
    return folder


def test_a_whole_run_has_no_problems(run):
    from motoflex_ros.report.run_folder import run_problems
    assert run_problems(run) == []


def test_report_refuses_a_run_without_its_identification(run):
    """Issue 23, point 8: identification.json gone, status.json still 'complete': refused;
    with --allow-incomplete labelled at the top, and no identification made up offline."""
    (run / "identification.json").unlink()
    _refused(*_cli("report", run, "--quiet", cwd=run.parent), run,
             "the run recorded no identification.json", "--allow-incomplete")
    assert not (run / "report.html").exists()
    done, _ = _cli("report", run, "--quiet", "--allow-incomplete", cwd=run.parent)
    assert done.returncode == 0, done.stderr
    html = (run / "report.html").read_text()
    top = html.index('<p class="warning" id="warning">Incomplete run: ')
    assert top < html.index("<section")
    assert "the run recorded no identification.json" in html[top:top + 400]
    assert "an identification computed now would not be the run" in html
    assert not (run / "identify.json").exists()   # nothing computed and saved as the run's


@pytest.mark.parametrize("doctor", ["another run's bag", "status edited over a failed run",
                                    "identification from other inputs", "corrupt bag",
                                    "bag without identification"])
def test_report_refuses_inconsistent_run_files(run, tmp_path, doctor):
    if doctor == "another run's bag":
        other = _bag(tmp_path / "other")
        shutil.copy(mcap_bag.find_mcap(other), run / "example_0.mcap")
        shutil.copy(other / mcap_bag.METADATA_FILE, run / mcap_bag.METADATA_FILE)
        words = ("not the one the run recorded",)
    elif doctor == "status edited over a failed run":
        (run / "identification.json").unlink()   # what a failed run leaves
        write_status(run, "complete")
        words = ("no identification.json",)
    elif doctor == "identification from other inputs":
        made = json.loads((run / "provenance.json").read_text())
        made["inputs"] = {"/config/components/frame.yaml": "0" * 64}
        (run / "provenance.json").write_text(json.dumps(made))
        results = json.loads((run / "identification.json").read_text())
        results["frame"]["inputs"] = {"/config/components/frame.yaml": "1" * 64}
        (run / "identification.json").write_text(json.dumps(results))
        words = ("'frame' came from /config/components/frame.yaml", "not the run's input")
    elif doctor == "corrupt bag":
        number, offset = _corrupt_middle_chunk(run)
        words = (f"chunk {number} of", f"byte offset {offset}")
    else:
        other = _bag(tmp_path / "other")
        shutil.copy(mcap_bag.find_mcap(other), run / "example_0.mcap")
        shutil.copy(other / mcap_bag.METADATA_FILE, run / mcap_bag.METADATA_FILE)
        made = json.loads((run / "provenance.json").read_text())
        made.pop("bag")
        (run / "provenance.json").write_text(json.dumps(made))
        words = ("holds no /identification/results",)
    _refused(*_cli("report", run, "--no-compute", "--quiet", cwd=run.parent), run,
             "missing or inconsistent", *words)
    assert not (run / "report.html").exists()
