"""The bad-input cases of test_bad_inputs that start the vehicle_simulator node: a file of
its own because each starts a ROS node process (test/conftest.py: ROS_FILES)."""
import pytest
from test_bad_inputs import CASES, NODE, assert_refused


@pytest.fixture
def node_env(tmp_path_factory):
    """A private ROS domain and log folder for the node cases (outside the case's folder)."""
    from motoflex_ros.launcher.domain import DomainLock
    from motoflex_ros.launcher.graph import ros_env
    with DomainLock() as lock:
        yield ros_env(lock.domain_id, tmp_path_factory.mktemp("ros_log"))


@pytest.mark.parametrize("name", sorted(n for n in CASES if CASES[n].node))
def test_bad_node_input_is_refused_in_one_line(name, tmp_path, node_env):
    folder = tmp_path / "case"
    folder.mkdir()
    assert_refused(CASES[name], folder, NODE, node_env)
