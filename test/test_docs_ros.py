"""The getting-started page's examples that start ROS 2 nodes (``motoflex replay``), run as
written; with the other ROS graph tests (module marker ``ros``), so they never meet a fault
test's graph. The rest of the documentation tests: ``test_docs.py``."""
import pytest
from doc_pages import example_folder, examples, run_example

pytestmark = pytest.mark.ros


@pytest.mark.parametrize("example", examples(ros=True), ids=lambda e: f"line{e[1]}")
def test_getting_started_ros_example_runs(example, tmp_path, monkeypatch):
    text, line = example
    monkeypatch.setenv("ROS_LOG_DIR", str(tmp_path / "ros_log"))
    monkeypatch.delenv("ROS_DOMAIN_ID", raising=False)   # the verb takes a free domain itself
    done = run_example(text, example_folder(tmp_path))
    assert done.returncode == 0, f"getting-started.md:{line}\n{text}\n{done.stderr[-2000:]}"
