"""The solid mesh component of test_mesh_chain through the ROS graph (``motoflex campaign``):
a file of its own because it starts node processes (test/conftest.py: ROS_FILES)."""
import json
import subprocess
import sys

import pytest
from test_campaign_graph import SHORT_PROTOCOL

from motoflex_ros.bench.offline_campaign import run_campaign, setup_campaign
from motoflex_ros.formats.component_file import load_component
from motoflex_ros.formats.mesh_examples import write_bracket_component


def run_cli(*args):
    """The stdout of ``motoflex args`` in a process of its own (the campaign starts ROS nodes)."""
    result = subprocess.run([sys.executable, "-m", "motoflex_ros.cli.main", *args],
                            capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    assert "Traceback" not in result.stderr
    return result.stdout


@pytest.fixture
def bracket(tmp_path):
    return str(write_bracket_component(tmp_path / "bracket"))


def test_campaign_graph_runs_a_mesh_file_and_draws_it(bracket, tmp_path):
    """``motoflex campaign --components FILE``: the mesh component's bench topics go by its name
    (/bench/bracket/...), the graph identifies what ``identify`` does offline (same samples, same
    numbers), the run folder names the file (component_files.json) and the rerun recording draws
    the mesh on the bench. On the short protocol (test/data/short_bench.yaml: every test kind,
    411 samples instead of 5,270): the mesh file's way through the graph is the point."""
    from motoflex_ros.record.rerun_readback import entity_rows
    bag = tmp_path / "run"
    out = json.loads(run_cli("campaign", "--component", bracket, "--report", "quick",
                             "--out", str(bag), "--json", "--protocol", SHORT_PROTOCOL))
    offline = run_campaign(setup_campaign(load_component(bracket), SHORT_PROTOCOL),
                           seed=0).identification.to_dict()
    assert out["bracket"]["static"]["k"] == pytest.approx(offline["static"]["k"], rel=1e-9)
    assert out["bracket"]["k_t"] == pytest.approx(offline["k_t"], rel=1e-9)
    assert json.loads((bag / "component_files.json").read_text()) == {"bracket": bracket}
    rows = entity_rows(bag / "run.rrd")
    assert rows.get("/bench/bracket/structure", 0) > 0
