"""provenance.json (issue 16, point 7): what a campaign records about how its run was made.

Each field is checked against where it comes from, found independently: the package version,
`git rev-parse HEAD` of the checkout, the shipped protocols' sensor noise, the arguments.
"""
import json
import shutil
import subprocess
from pathlib import Path

import pytest

import motoflex_ros
from motoflex_ros.bench.protocols import load_protocol, protocol_for
from motoflex_ros.launcher.provenance import (
    PROVENANCE_FILE,
    read_provenance,
    sensor_noise,
    write_provenance,
)
from motoflex_ros.structures.paper_tables import COMPONENTS

ROOT = Path(motoflex_ros.__file__).resolve().parents[1]


def _git(*args):
    if shutil.which("git") is None:
        return None
    result = subprocess.run(["git", "-C", str(ROOT), *args], capture_output=True, text=True)
    return result.stdout.strip() if result.returncode == 0 else None


def test_provenance_records_the_run(tmp_path):
    argv = ["campaign", "--out", "bags/x y", "--seed", "7"]
    path = write_provenance(tmp_path, argv, list(COMPONENTS), 7, None, None, 0.0)
    assert path == tmp_path / PROVENANCE_FILE
    record = json.loads(path.read_text())
    assert record["command"] == "motoflex campaign --out 'bags/x y' --seed 7"
    assert record["package_version"] == motoflex_ros.__version__
    assert record["started_utc"] == "1970-01-01T00:00:00Z"
    assert (record["seed"], record["noise_override_m"]) == (7, None)
    assert record["sensor_noise_m"] == {c: protocol_for(c).sensor.noise_m for c in COMPONENTS}
    head = _git("rev-parse", "HEAD")
    assert record["git_commit"] == head
    if head is None:
        assert record["git_note"]
    else:
        assert record["git_dirty"] == bool(_git("status", "--porcelain",
                                                "--untracked-files=no"))
    assert read_provenance(tmp_path) == record


def test_provenance_noise_override_and_protocol_file():
    assert sensor_noise(["frame", "swingarm"], noise_override=3e-5) == {"frame": 3e-5,
                                                                      "swingarm": 3e-5}
    expected = load_protocol("default").sensor.noise_m
    assert sensor_noise(["frame"], protocol="default") == {"frame": expected}


@pytest.mark.parametrize("text", ["{not json", "[1, 2]"])
def test_unreadable_provenance_is_reported_not_guessed(tmp_path, text):
    (tmp_path / PROVENANCE_FILE).write_text(text)
    assert "unreadable" in read_provenance(tmp_path)
    from motoflex_ros.report.provenance_section import provenance_table
    rows = {r[0].text: r for r in provenance_table(tmp_path).rows}
    assert rows["seed"][1].text == "not recorded" and PROVENANCE_FILE in rows["seed"][2].text
    assert read_provenance(tmp_path / "missing") is None
