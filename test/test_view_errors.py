"""`motoflex view` on a path that is not a run folder: one clear line, exit code 2."""
import subprocess
import sys

import pytest


def view(*args):
    return subprocess.run([sys.executable, "-m", "motoflex_ros.cli.main", "view", *args],
                          capture_output=True, text=True, timeout=60)


@pytest.mark.parametrize("web", [[], ["--web"]])
def test_view_missing_folder_is_a_clear_error(tmp_path, web):
    result = view(str(tmp_path / "no_such_run"), *web)
    assert result.returncode == 2
    assert "not a run folder" in result.stderr
    assert "Traceback" not in result.stderr


def test_view_folder_without_run_files_is_a_clear_error(tmp_path):
    (tmp_path / "notes.txt").write_text("not a run")
    result = view(str(tmp_path), "--web")
    assert result.returncode == 2
    assert "not a run folder" in result.stderr


def test_view_file_instead_of_folder_is_a_clear_error(tmp_path):
    path = tmp_path / "run.rrd"
    path.write_bytes(b"garbage")
    result = view(str(path))
    assert result.returncode == 2
    assert "not a run folder" in result.stderr
