"""package.xml resolves with rosdep on Jazzy and a colcon build is quiet (issue 24, point 3).

test/data/jazzy_rosdep_keys.txt holds the names of ros/rosdistro's rosdep keys (rosdep/base.yaml
and python.yaml) that resolve on Jazzy's Ubuntu (noble), and the Jazzy packages package.xml
names (jazzy/distribution.yaml), written by tools/rosdep_keys.py from a rosdistro checkout.
"""
import ast
import re
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
KEYS = ROOT / "test" / "data" / "jazzy_rosdep_keys.txt"

# what a top-level import of motoflex_ros needs: a rosdep key, or the pip distribution that
# package.xml's pip-only comment must name; None: an optional extra (setup.py "scale")
IMPORT_TO_DEPENDENCY = {
    "numpy": "python3-numpy", "scipy": "python3-scipy", "yaml": "python3-yaml",
    "pandas": "python3-pandas", "matplotlib": "python3-matplotlib", "tqdm": "python3-tqdm",
    "meshio": "python3-meshio", "rosbags": "python3-rosbags-pip",
    "statsmodels": "pip:statsmodels", "skfem": "pip:scikit-fem", "mcap": "pip:mcap",
    "mcap_ros2": "pip:mcap-ros2-support", "rerun": "pip:rerun-sdk",
    "rerun_cli": "pip:rerun-sdk",
    "pymoo": "pip:pymoo", "distributed": None, "dask": None, "pypardiso": None,
}
ROS_MESSAGES = re.compile(r"^(rclpy|rcl_interfaces|builtin_interfaces|\w+_msgs)$")


def _keys():
    return {line for line in KEYS.read_text().splitlines() if line and not line[0] == "#"}


def _depends():
    root = ET.parse(ROOT / "package.xml").getroot()
    return {tag: [e.text.strip() for e in root.iter(tag)]
            for tag in ("depend", "build_depend", "exec_depend", "test_depend")}


def _pip_only_comment():
    text = (ROOT / "package.xml").read_text()
    comments = re.findall(r"<!--(.*?)-->", text, re.S)
    return next((c for c in comments if "pip install" in c), "")


def _imports(folder):
    names = set()
    for path in folder.rglob("*.py"):
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.Import):
                names.update(a.name.split(".")[0] for a in node.names)
            elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
                names.add(node.module.split(".")[0])
    return names - set(sys.stdlib_module_names) - {"motoflex_ros"}


def test_every_dependency_is_a_jazzy_rosdep_key():
    keys = _keys()
    assert len(keys) > 1000 and "python3-numpy" in keys and "rclpy" in keys
    declared = [name for names in _depends().values() for name in names]
    assert declared
    unknown = sorted(set(declared) - keys)
    assert not unknown, f"package.xml: not a rosdep key or Jazzy package: {unknown}"


def test_the_key_list_rejects_what_rosdep_rejects():
    """The keys issue 24 found wrong are not in the list, their replacements are."""
    keys = _keys()
    assert {"python3-statsmodels", "python3-scikit-fem", "python3-skfem"}.isdisjoint(keys)
    assert {"python3-meshio", "python3-pandas", "launch", "launch_ros"} <= keys


def test_every_import_is_declared():
    depends = {n for names in _depends().values() for n in names}
    pip_only = _pip_only_comment()
    missing = []
    for name in sorted(_imports(ROOT / "motoflex_ros")):
        if ROS_MESSAGES.match(name):
            need = name
        elif name in IMPORT_TO_DEPENDENCY:
            need = IMPORT_TO_DEPENDENCY[name]
        else:
            missing.append(f"{name} (unknown import: add it to IMPORT_TO_DEPENDENCY)")
            continue
        if need is None:
            continue
        found = (need[4:] in pip_only) if need.startswith("pip:") else need in depends
        if not found:
            missing.append(f"{name} needs {need}")
    assert not missing, missing


def test_build_prints_no_package_would_be_ignored(tmp_path):
    """A colcon build (``setup.py egg_info build``): the config/ folders (importable as namespace
    packages) raise no setuptools "Package would be ignored" warning."""
    src = tmp_path / "src"
    src.mkdir()
    for name in ("setup.py", "setup.cfg", "package.xml"):
        shutil.copy(ROOT / name, src / name)
    for name in ("resource", "motoflex_ros", "launch"):
        shutil.copytree(ROOT / name, src / name,
                        ignore=shutil.ignore_patterns("__pycache__", "*.pyc"))
    (src / "config").symlink_to("motoflex_ros/config")
    build = subprocess.run([sys.executable, "setup.py", "egg_info", "build", "--build-base",
                            str(tmp_path / "build")], cwd=src, capture_output=True, text=True,
                           timeout=300)
    assert build.returncode == 0, build.stderr[-2000:]
    assert "would be ignored" not in build.stdout + build.stderr
    data = tmp_path / "build" / "lib" / "motoflex_ros" / "config"
    shipped = {p.relative_to(ROOT / "motoflex_ros" / "config")
               for p in (ROOT / "motoflex_ros" / "config").rglob("*") if p.is_file()}
    assert shipped and {p.relative_to(data) for p in data.rglob("*") if p.is_file()} == shipped
