"""A run folder's status.json (issue 13, point 4): written last, 'complete' or 'failed' with the
reason; a failed run keeps no result; report and replay refuse an incomplete run unless
--allow-incomplete, and the report then says so at the top."""
import json
import subprocess
import sys
from pathlib import Path

import pytest
from hostile import run_motoflex

from motoflex_ros.errors import MotoflexError
from motoflex_ros.launcher.status import (
    STATUS_FILE,
    IncompleteRun,
    incomplete_reason,
    read_status,
    require_complete,
    run_status,
    staged,
    write_status,
)
from motoflex_ros.record.mcap_bag import BagError, BagWriter

EXAMPLE = Path(__file__).resolve().parents[1] / "bags" / "example"
RESULT = "identification.json"


def _cli(*argv):
    """``report`` in this process (hostile.run_motoflex); ``replay`` (ROS nodes for
    --identify) in a process of its own."""
    if argv[0] != "replay":
        return run_motoflex(argv)
    return subprocess.run([sys.executable, "-m", "motoflex_ros.cli.main", *map(str, argv)],
                          capture_output=True, text=True, timeout=120)


def _bag(path):
    """A small real bag (what bag_info and replay read), no status."""
    with BagWriter(path) as writer:
        writer.add_topic("/clock", "rosgraph_msgs/msg/Clock")
        for k in range(3):
            writer.write("/clock", 10**9 * k, bytes(12))
    return path


def test_complete_run_status_written_last(tmp_path):
    run = tmp_path / "run"
    with run_status(run, [RESULT]) as folder:
        folder.mkdir()
        (folder / RESULT).write_text("{}")
        assert read_status(folder) is None   # not before the end
    status = read_status(run)
    assert status["status"] == "complete" and status["reason"] is None
    assert (run / RESULT).is_file()
    assert max(p.stat().st_mtime_ns for p in run.iterdir()) == \
        (run / STATUS_FILE).stat().st_mtime_ns
    assert require_complete(run) is None


@pytest.mark.parametrize("error, reason", [
    (MotoflexError("node 'recorder' died (killed by SIGKILL)"),
     "node 'recorder' died (killed by SIGKILL)"),
    (KeyboardInterrupt(), "interrupted by SIGINT"),
    (KeyboardInterrupt("SIGTERM"), "interrupted by SIGTERM"),
    (OSError(28, "No space left on device"), "OSError: [Errno 28] No space left on device"),
])
def test_failed_run_keeps_no_result(tmp_path, error, reason):
    run = tmp_path / "run"
    with pytest.raises(type(error)), run_status(run, [RESULT, "report.html"]):
        run.mkdir()
        (run / "run_0.mcap").write_bytes(b"bag")
        (run / RESULT).write_text("{}")   # success-looking results, final and staged
        staged(run / "report.html").write_text("<html>")
        raise error
    assert read_status(run) | {"time_utc": None} == {"status": "failed", "reason": reason,
                                                      "time_utc": None}
    assert sorted(p.name for p in run.iterdir()) == ["run_0.mcap", STATUS_FILE]
    with pytest.raises(IncompleteRun, match="--allow-incomplete"):
        require_complete(run)
    assert reason in require_complete(run, allow_incomplete=True)


def test_failure_before_the_folder_exists_writes_nothing(tmp_path):
    with pytest.raises(MotoflexError), run_status(tmp_path / "run"):
        raise MotoflexError("protocol.yaml: key 'x': bad")
    assert not (tmp_path / "run").exists()


def test_existing_folder_refused_untouched(tmp_path):
    run = tmp_path / "run"
    run.mkdir()
    (run / RESULT).write_text("{}")
    with pytest.raises(BagError, match="not an empty directory"), run_status(run, [RESULT]):
        pytest.fail("the body must not run")
    assert [p.name for p in run.iterdir()] == [RESULT]


def test_staged_name_hidden_same_suffix(tmp_path):
    assert staged(tmp_path / "identification.json").name == ".identification.partial.json"


def test_what_counts_as_incomplete(tmp_path):
    outputs = tmp_path / "outputs"   # only verbs' JSON outputs: not a recorded run
    outputs.mkdir()
    (outputs / "eig.json").write_text("{}")
    assert incomplete_reason(outputs) is None
    bag = _bag(tmp_path / "bag")
    assert "did not finish (no status.json" in incomplete_reason(bag)
    write_status(bag, "failed", "interrupted by SIGINT")
    assert "the run failed (interrupted by SIGINT)" in incomplete_reason(bag)
    (bag / STATUS_FILE).write_text("{not json")
    assert "unreadable" in incomplete_reason(bag)
    write_status(bag, "complete")
    assert incomplete_reason(bag) is None


def test_example_run_is_complete():
    if not (EXAMPLE / "metadata.yaml").is_file():
        pytest.skip("bags/example is not in this checkout")
    assert read_status(EXAMPLE)["status"] == "complete"


def _failed_run(tmp_path):
    """The folder a SIGINT right after identification left before issue 13: a bag and a
    complete identification.json, status failed."""
    run = _bag(tmp_path / "run")
    (run / RESULT).write_text(json.dumps({}))
    write_status(run, "failed", "interrupted by SIGINT; every node stopped")
    return run


def test_report_refuses_incomplete_run(tmp_path):
    run = _failed_run(tmp_path)
    cli = _cli("report", run, "--no-compute", "--quiet")
    assert cli.returncode == 2, cli.stderr
    assert "the run failed (interrupted by SIGINT" in cli.stderr
    assert "--allow-incomplete" in cli.stderr and "Traceback" not in cli.stderr
    assert not (run / "report.html").exists()
    (run / STATUS_FILE).unlink()   # killed before its status: refused as well
    cli = _cli("report", run, "--no-compute", "--quiet")
    assert cli.returncode == 2 and "did not finish" in cli.stderr


def test_report_of_incomplete_run_says_so_at_the_top(tmp_path):
    run = _failed_run(tmp_path)
    cli = _cli("report", run, "--no-compute", "--quiet", "--allow-incomplete")
    assert cli.returncode == 0, cli.stderr
    assert "warning:" in cli.stdout and "interrupted by SIGINT" in cli.stdout
    html = (run / "report.html").read_text()
    top = html.index('<p class="warning" id="warning">Incomplete run: ')
    assert top < html.index("<section") and "interrupted by SIGINT" in html[top:top + 300]
    # issue 23, point 8: a status.json edited to "complete" over files that are not a whole
    # run (no results, no provenance) is refused, and labelled with --allow-incomplete
    write_status(run, "complete")
    cli = _cli("report", run, "--no-compute", "--quiet")
    assert cli.returncode == 2 and "missing or inconsistent" in cli.stderr, cli.stderr
    cli = _cli("report", run, "--no-compute", "--quiet", "--allow-incomplete")
    assert cli.returncode == 0, cli.stderr
    html = (run / "report.html").read_text()
    top = html.index('<p class="warning" id="warning">Incomplete run: ')
    assert top < html.index("<section") and "no provenance.json" in html[top:top + 400]


@pytest.mark.parametrize("identify", [False, True])
def test_replay_refuses_incomplete_run(tmp_path, identify):
    run = _failed_run(tmp_path)
    cli = _cli("replay", run, *(["--identify", tmp_path / "out.json"] if identify else []))
    assert cli.returncode == 2, cli.stderr
    assert "the run failed" in cli.stderr and "--allow-incomplete" in cli.stderr
    assert "Traceback" not in cli.stderr and not (tmp_path / "out.json").exists()
