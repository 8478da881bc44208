"""colcon-style install (setup.py install --prefix): node executables under lib/motoflex_ros."""
import ast
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def _console_scripts():
    tree = ast.parse((ROOT / "setup.py").read_text())
    for node in ast.walk(tree):
        if isinstance(node, ast.Dict):
            for key, value in zip(node.keys, node.values):
                if isinstance(key, ast.Constant) and key.value == "console_scripts":
                    return [ast.literal_eval(v).split("=")[0].strip() for v in value.elts]
    raise AssertionError("no console_scripts in setup.py")


def _imported_packages(path):
    """Top-level names of the modules a Python file imports."""
    tree = ast.parse(path.read_text())
    names = {alias.name for node in ast.walk(tree) if isinstance(node, ast.Import)
             for alias in node.names}
    names |= {node.module for node in ast.walk(tree)
              if isinstance(node, ast.ImportFrom) and node.module and node.level == 0}
    return {name.split(".")[0] for name in names}


def test_package_xml_exec_depends_on_what_the_launch_files_import():
    """Package.xml declares what rosdep must install for the launch files (issue 16, point
    9): every ROS package a shipped launch file imports, and launch_ros, which `ros2 launch`
    loads for any."""
    depends = {e.text for e in ET.parse(ROOT / "package.xml").getroot().iter("exec_depend")}
    launch_files = sorted((ROOT / "launch").glob("*.launch.py"))
    assert launch_files
    imported = set().union(*map(_imported_packages, launch_files))
    ros_packages = imported - set(sys.stdlib_module_names) - {"motoflex_ros", "yaml"}
    assert "launch" in ros_packages
    assert ros_packages | {"launch_ros"} <= depends, ros_packages - depends
    assert "yaml" not in imported or "python3-yaml" in depends


NODES = ("sim_clock", "recorder", "bag_replay", "load_actuator", "component_simulator",
         "displacement_sensor", "identification", "vehicle_simulator")


@pytest.mark.slow
def test_ros_install_prefix_puts_executables_in_lib_package(tmp_path):
    src = tmp_path / "src"
    ignore = shutil.ignore_patterns("__pycache__", "*.egg-info", "build", "*.pyc")
    src.mkdir()
    for name in ("setup.py", "setup.cfg", "package.xml"):
        shutil.copy(ROOT / name, src / name)
    for name in ("resource", "config", "motoflex_ros", "launch"):
        if (ROOT / name).exists():
            shutil.copytree(ROOT / name, src / name, ignore=ignore, symlinks=True)
    prefix, record = tmp_path / "install", tmp_path / "record.txt"
    build = subprocess.run(
        [sys.executable, "setup.py", "egg_info", "build", "install", "--prefix", str(prefix),
         "--single-version-externally-managed", "--record", str(record)],
        cwd=src, capture_output=True, text=True, timeout=600)
    assert build.returncode == 0, build.stderr[-2000:]
    lib = prefix / "lib" / "motoflex_ros"
    scripts = _console_scripts()
    assert set(NODES) <= set(scripts)
    for name in scripts:
        assert (lib / name).is_file() and (lib / name).stat().st_mode & 0o111, name
    assert (prefix / "share" / "motoflex_ros" / "package.xml").is_file()
    site = next(prefix.glob("lib/python3*/site-packages"))
    # the ament package marker: what `ros2 run` / `ros2 pkg` use to find the package
    index = subprocess.run(
        [sys.executable, "-c", "from ament_index_python.packages import "
         "get_package_share_directory as g; print(g('motoflex_ros'))"],
        capture_output=True, text=True, timeout=120,
        env={"AMENT_PREFIX_PATH": str(prefix), "PATH": "/usr/bin:/bin"})
    assert index.returncode == 0, index.stderr
    assert Path(index.stdout.strip()) == prefix / "share" / "motoflex_ros"
    run = subprocess.run([str(lib / "sim_clock"), "--ros-args", "-p", "window:=0"],
                         capture_output=True, text=True, timeout=120,
                         env={"PYTHONPATH": str(site), "ROS_LOG_DIR": str(tmp_path / "log"),
                              "ROS_DOMAIN_ID": "101", "HOME": str(tmp_path)})
    assert run.returncode == 2, run.stderr
    assert "parameter 'window' = 0 is not allowed" in run.stderr
    assert (site / "motoflex_ros" / "nodes" / "sim_clock.py").is_file()
    # the DDS profile every node loads (loopback only, issue 13) is package data too
    assert (site / "motoflex_ros" / "config" / "dds" / "loopback.xml").is_file()
