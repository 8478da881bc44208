"""Node parameters (issue 16, point 6): who a params file's parameters are for, the wrong-type
message, and every node executable's ``--help``."""
import re
import subprocess
import sys
from pathlib import Path

import pytest

from motoflex_ros.nodes.params import Param, ParameterError
from motoflex_ros.nodes.ros_args import params_files, wildcard_only_names

ROOT = Path(__file__).resolve().parents[1]
NODE_SCRIPTS = re.findall(r'"(\w+) = (motoflex_ros\.nodes\.\w+):main"',
                          (ROOT / "setup.py").read_text())


def test_wildcard_only_names_of_params_files(tmp_path):
    wildcard = tmp_path / "all.yaml"
    wildcard.write_text("/**:\n  ros__parameters:\n    seed: 1\n    dt: 0.01\n"
                        "    qos: {depth: 5}\n"
                        "/bike1/*:\n  ros__parameters:\n    rate: 2.0\n")
    named = tmp_path / "named.yaml"
    named.write_text("/bike1:\n  sim_clock:\n    ros__parameters:\n      dt: 0.001\n"
                     "other_node:\n  ros__parameters:\n    window: 3\n")
    argv = ["sim_clock", "--ros-args", "--params-file", str(wildcard), "-p", "rate:=1.0",
            "--", "--params-file", "not-a-ros-arg.yaml",
            "--ros-args", "--params-file", str(named)]
    assert params_files(argv) == [str(wildcard), str(named)]
    # dt is named for /bike1/sim_clock, rate is given with -p: both are this node's
    assert wildcard_only_names(argv, "/bike1/sim_clock") == {"seed", "qos.depth"}
    # in the root namespace the nested section is another node's
    assert wildcard_only_names(argv, "/sim_clock") == {"seed", "qos.depth", "dt"}
    assert wildcard_only_names(["x", "--ros-args", "--params-file",
                                str(tmp_path / "missing.yaml")], "/sim_clock") == set()


def test_param_wrong_type_message():
    dt = Param("dt", 0.001, 1e-6, 1.0, description="step [s]")
    with pytest.raises(ParameterError) as wrong:
        dt.check("sim_clock", "fast")
    assert str(wrong.value) == ("node 'sim_clock': parameter 'dt' = 'fast' has the wrong type "
                                "(expected float in [1e-06, 1])")
    with pytest.raises(ParameterError) as out_of_range:
        dt.check("sim_clock", 2)
    assert str(out_of_range.value) == ("node 'sim_clock': parameter 'dt' = 2 is not allowed "
                                       "(expected float in [1e-06, 1])")
    assert dt.check("sim_clock", 1) == 1.0


def test_node_scripts_found():
    assert len(NODE_SCRIPTS) == 8


@pytest.mark.parametrize("script, module", NODE_SCRIPTS)
def test_node_help_lists_parameters_and_exits(script, module):
    """``<node> --help`` prints every parameter with its default and exits 0 (it used to start
    the node and wait for its graph, forever)."""
    import importlib

    from motoflex_ros.nodes.rig_node import RigNode
    result = subprocess.run([sys.executable, "-m", module, "--help"], capture_output=True,
                            text=True, timeout=60)
    assert result.returncode == 0, result.stderr
    assert result.stdout.startswith(f"usage: {script} ")
    (node_class,) = [c for c in vars(importlib.import_module(module)).values()
                     if isinstance(c, type) and issubclass(c, RigNode) and c.NAME == script]
    lines = result.stdout.splitlines()
    for param in node_class.PARAMS:
        default = list(param.default) if param.kind == "str[]" else param.default
        assert any(line.split()[:1] == [param.name] and f"default {default!r}:" in line
                   for line in lines), (param.name, result.stdout)
