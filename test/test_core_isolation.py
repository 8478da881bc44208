"""The numerical core imports no middleware: rclpy, rerun, mcap and matplotlib are blocked."""
import pkgutil
import subprocess
import sys
from pathlib import Path

import motoflex_ros

CORE = ("lumped_stiffness", "structures", "bench", "identify", "vehicle", "study")
BLOCKED = ("rclpy", "rerun", "mcap", "mcap_ros2", "matplotlib", "rosbags")


def core_modules():
    root = Path(motoflex_ros.__file__).parent
    names = []
    for pkg in CORE:
        if not (root / pkg / "__init__.py").exists():
            continue
        names.append(f"motoflex_ros.{pkg}")
        for info in pkgutil.iter_modules([str(root / pkg)]):
            names.append(f"motoflex_ros.{pkg}.{info.name}")
    return names


def test_core_imports_without_middleware():
    modules = core_modules()
    assert "motoflex_ros.lumped_stiffness.axis" in modules
    script = (
        "import sys, importlib\n"
        f"for name in {BLOCKED!r}:\n"
        "    sys.modules[name] = None\n"
        f"for name in {modules!r}:\n"
        "    importlib.import_module(name)\n"
        "print('ok')\n")
    result = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
