"""launch/campaign.launch.py (only where the ROS 2 ``launch`` package is importable)."""
import importlib.util
from pathlib import Path

import pytest

pytest.importorskip("launch.launch_description")  # the ROS 2 package, not ./launch/
import launch  # noqa: E402

LAUNCH_FILE = Path(__file__).resolve().parents[1] / "launch" / "campaign.launch.py"


def test_campaign_launch_same_graph_as_cli(tmp_path):
    from motoflex_ros.launcher.campaign import campaign_specs
    spec = importlib.util.spec_from_file_location("campaign_launch", LAUNCH_FILE)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    description = module.generate_launch_description()
    context = launch.LaunchContext()
    for action in description.entities:
        if isinstance(action, launch.actions.DeclareLaunchArgument):
            action.execute(context)
    context.launch_configurations["out"] = str(tmp_path / "bag")
    actions = module._graph(context)
    names = [a.name for a in actions if isinstance(a, launch.actions.ExecuteProcess)]
    expected = [s.name for s in campaign_specs(["frame", "front_assembly", "swingarm"],
                                               tmp_path / "bag")]
    assert names == expected
