"""Test helper: the example run converted to a rerun recording and reported, once per test run.

Several test files read the same products of bags/example: its recording (``motoflex rerun``:
test_rerun_blueprint.py, test_rerun_browser.py) and its report (``motoflex report
--no-compute``: test_report_summary.py, test_report_browser.py). The first test process that
needs one makes it in a copy of bags/example under ``MOTOFLEX_TEST_SHARED`` (a folder of the
test run that test/conftest.py creates and both xdist workers inherit); a process that comes
while it is being made waits on the lock and then reads the same folder. Readers must not
write into it: a test that changes the run folder copies it first.
"""
import fcntl
import os
import shutil
from pathlib import Path

import pytest
from hostile import run_motoflex
from report_html import EXAMPLE, example_report

__all__ = ["SHARED_ENV", "example_recording", "example_reported"]

SHARED_ENV = "MOTOFLEX_TEST_SHARED"


def _made_once(name, make):
    """The folder ``<shared>/<name>/example`` that ``make(<shared>/<name>)`` made (a copy of
    bags/example and its product), made by the first caller of this test run."""
    if not (EXAMPLE / "metadata.yaml").is_file():
        pytest.skip("bags/example is not in this checkout")
    shared = Path(os.environ[SHARED_ENV])
    done = shared / f"{name}.done"
    parent = shared / name
    with open(shared / f"{name}.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)   # released when the file closes
        if not done.exists():
            shutil.rmtree(parent, ignore_errors=True)   # a failed earlier attempt
            parent.mkdir()
            make(parent)
            done.touch()
    return parent / "example"


def _converted(parent):
    """A copy of bags/example in ``parent`` (without its recording and report), converted."""
    folder = parent / "example"
    shutil.copytree(EXAMPLE, folder, ignore=shutil.ignore_patterns("*.rrd", "report.html"))
    result = run_motoflex(["rerun", folder])
    assert result.returncode == 0, result.stderr[-2000:]


def example_recording():
    """The example run's folder holding ``example.rrd`` as ``motoflex rerun`` writes it."""
    return _made_once("recording", _converted)


def example_reported():
    """The example run's folder holding ``report.html`` as ``motoflex report --no-compute``
    writes it (:func:`report_html.example_report`)."""
    return _made_once("report", example_report)
