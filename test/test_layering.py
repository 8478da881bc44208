"""The layer order (issue 25, point 1; docs/architecture.md): the import-linter contract in
pyproject.toml, run as a test, and proof that it catches a reversed import.

grimp (under import-linter) reads every import statement of the package, the ones inside
functions too, so a lazy import cannot hide a reversed dependency or a cycle. The former ad-hoc
rules of this file are contracts now: nodes below the CLI, the vehicle independent of the
identification, structures below vehicle and study (the layers contract) and the record layer
reaching no engine but through the bench replay (a forbidden contract). The numerical core
reads no file format (issue 25, point 2): it imports neither ``motoflex_ros.formats`` nor
meshio (a forbidden contract; the layers forbid formats too).
"""
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import motoflex_ros

PACKAGE = Path(motoflex_ros.__file__).parent
ROOT = PACKAGE.parent
PYPROJECT = ROOT / "pyproject.toml"
LINT_IMPORTS = Path(sys.executable).with_name("lint-imports")


def lint_imports(where):
    """Run ``lint-imports`` on the package found first on the path at ``where``."""
    if not LINT_IMPORTS.exists():
        pytest.fail("lint-imports is missing: install the test extra (pip install -e .[test])")
    return subprocess.run([str(LINT_IMPORTS), "--no-cache", str(PYPROJECT)], cwd=where,
                          env={"PYTHONPATH": str(where), "PATH": "/usr/bin:/bin"},
                          capture_output=True, text=True)


def copy_of_the_package(tmp_path):
    shutil.copytree(PACKAGE, tmp_path / "motoflex_ros",
                    ignore=shutil.ignore_patterns("__pycache__", "config"))
    return tmp_path


def test_the_import_contract_is_kept():
    result = lint_imports(ROOT)
    assert result.returncode == 0, result.stdout + result.stderr
    assert "0 broken" in result.stdout


@pytest.mark.parametrize("module, injected, broken", [
    # an upward import inside a function: the core reaching the CLI
    ("structures/beam.py", "def _reversed():\n    from motoflex_ros.cli import main\n",
     "motoflex_ros.structures.beam -> motoflex_ros.cli.main"),
    # a cycle inside a package hidden in a function
    ("launcher/run_failures.py", "def _cycle():\n    from motoflex_ros.launcher import run\n",
     "No cycles are allowed in motoflex_ros.launcher"),
    # the core importing a middleware library
    ("identify/peaks.py", "def _middleware():\n    import rclpy\n",
     "motoflex_ros.identify.peaks -> rclpy"),
    # the core reading a file format: the bench loading its component by name again
    ("bench/offline_campaign.py",
     "def _by_name():\n    from motoflex_ros.formats.component_file import load_component\n",
     "motoflex_ros.bench.offline_campaign -> motoflex_ros.formats.component_file"),
    # ... or the structures reading a mesh file themselves
    ("structures/mesh_component.py", "def _reader():\n    import meshio\n",
     "motoflex_ros.structures.mesh_component -> meshio"),
])
def test_the_contract_catches_a_reversed_import(tmp_path, module, injected, broken):
    """A copy of the package with one import added at the end of one module (inside a function,
    where a lazy import would hide it) breaks the contract, naming the import."""
    copy = copy_of_the_package(tmp_path)
    assert lint_imports(copy).returncode == 0   # the copy is linted, and kept as it is
    path = copy / "motoflex_ros" / module
    path.write_text(path.read_text() + "\n\n" + injected)
    result = lint_imports(copy)
    assert result.returncode == 1, result.stdout + result.stderr
    assert broken in result.stdout, result.stdout
