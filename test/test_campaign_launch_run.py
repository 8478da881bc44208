"""A real run of launch/campaign.launch.py by ROS 2's ``LaunchService`` (test_campaign_launch
says why it is skipped where PyPI's packages are all there is): a file of its own because it
starts the campaign's node processes (test/conftest.py: ROS_FILES)."""
import os

import pytest
from test_campaign_launch import LAUNCH_FILE, _real_launch


def test_campaign_launch_runs_to_its_end(tmp_path, monkeypatch):
    launch = _real_launch()
    if launch is None:
        pytest.skip("ROS 2 launch is not importable (not on PyPI)")
    pytest.importorskip("rclpy")
    from launch.launch_description_sources import PythonLaunchDescriptionSource

    from motoflex_ros.launcher.domain import DomainLock
    with DomainLock() as free:
        monkeypatch.setenv("ROS_DOMAIN_ID", str(free.domain_id))
        monkeypatch.setenv("OPENBLAS_NUM_THREADS", "1")
        service = launch.LaunchService()
        service.include_launch_description(launch.actions.IncludeLaunchDescription(
            PythonLaunchDescriptionSource(str(LAUNCH_FILE)),
            launch_arguments={"components": "swingarm", "out": str(tmp_path / "bag")}.items()))
        assert service.run() == 0
    assert (tmp_path / "bag" / "identification.json").is_file()
    assert os.listdir(tmp_path / "bag")
