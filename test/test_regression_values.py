"""test/regression_values.json (test/regression.py): each value has a tolerance, the commit that
produced it (in this repository's history), a source, a test that reads it and a way to be
recomputed by tools/regenerate_regression_values.py."""
import importlib.util
import shutil
import subprocess
from pathlib import Path

import pytest
from regression import entries

ROOT = Path(__file__).resolve().parents[1]
TOOL = ROOT / "tools" / "regenerate_regression_values.py"


def _tool():
    spec = importlib.util.spec_from_file_location("regenerate_regression_values", TOOL)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_each_value_is_complete_and_recomputable():
    groups = _tool().GROUPS
    tests = "\n".join(p.read_text(encoding="utf-8") for p in ROOT.glob("test/test_*.py"))
    assert entries()
    for key, entry in entries().items():
        assert set(entry) - {"rel", "abs"} == {"value", "commit", "source"}, key
        assert ("rel" in entry) != ("abs" in entry), key
        assert key.split(".", 1)[0] in groups, key
        assert key.rsplit(".", 1)[0] in tests, f"{key}: no test reads it"


@pytest.mark.skipif(shutil.which("git") is None or not (ROOT / ".git").exists(),
                    reason="not a git checkout")
def test_each_commit_is_in_the_history():
    for key, entry in entries().items():
        found = subprocess.run(["git", "cat-file", "-e", f"{entry['commit']}^{{commit}}"],
                               cwd=ROOT, capture_output=True)
        assert found.returncode == 0, (key, entry["commit"])


def test_tool_refuses_an_unknown_group(capsys):
    with pytest.raises(SystemExit):
        _tool().main(["no_such_group"])
    assert "unknown group ['no_such_group']" in capsys.readouterr().err
