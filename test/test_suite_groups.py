"""test/conftest.py: the groups ./test.sh gives pytest-xdist and the markers given per file.

The scheduler is driven through xdist's public scheduler protocol (add_node,
add_node_collection, schedule, mark_test_complete) with stand-in workers that record what they
are sent: the ROS files' tests go to one worker, in their order, and each other file whole to
one worker. No worker process is started.
"""
from pathlib import Path
from types import SimpleNamespace

import pytest
from conftest import (
    FAULT_FILES,
    ROS_FILES,
    ROS_GROUP,
    SLOW_FILES,
    SLOW_TESTS,
    grouped_nodeid,
    pytest_collection_modifyitems,
    pytest_xdist_make_scheduler,
)

pytest.importorskip("xdist")

COLLECTION = ["test/test_faults.py::test_a", "test/test_faults.py::test_b[x@y]",
              "test/test_ros_nodes.py::test_c", "test/test_lumped.py::test_d",
              "test/test_lumped.py::test_e", "test/test_cli.py::test_f",
              "test/test_cli.py::test_g", "test/test_docs.py::test_h"]


class Worker:
    """A stand-in for xdist's WorkerController: records the indices it is asked to run."""

    def __init__(self, name):
        self.gateway = SimpleNamespace(id=name)
        self.sent, self.shutting_down = [], False

    def send_runtest_some(self, indices):
        self.sent.append(list(indices))

    def shutdown(self):
        self.shutting_down = True


def _config(dist):
    values = {"tx": ["2*popen"], "dist": dist}
    return SimpleNamespace(getvalue=values.__getitem__,
                           option=SimpleNamespace(loadscopereorder=False))


def _run(collection):
    """Schedule ``collection`` on two stand-in workers to its end; the runs of each worker."""
    sched = pytest_xdist_make_scheduler(_config("loadgroup"), None)
    workers = [Worker("gw0"), Worker("gw1")]
    for worker in workers:
        sched.add_node(worker)
    for worker in workers:
        sched.add_node_collection(worker, collection)
    sched.schedule()
    done = {w: 0 for w in workers}
    while not sched.tests_finished:
        for worker in workers:
            pending = [i for batch in worker.sent for i in batch][done[worker]:]
            if pending:
                sched.mark_test_complete(worker, pending[0])
                done[worker] += 1
    return {w.gateway.id: [collection[i] for batch in w.sent for i in batch] for w in workers}


def test_ros_files_run_on_one_worker_in_order_and_each_file_whole():
    runs = _run(COLLECTION)
    assert sorted(nodeid for run in runs.values() for nodeid in run) == sorted(COLLECTION)
    ros = [n for n in COLLECTION if n.split("::")[0].rsplit("/", 1)[1] in ROS_FILES]
    holder = [run for run in runs.values() if ros[0] in run]
    assert len(holder) == 1 and [n for n in holder[0] if n in ros] == ros
    assert holder[0][:len(ros)] == ros     # the first unit of its worker
    for name in ("test_lumped.py", "test_cli.py"):
        assert sum(any(name in n for n in run) for run in runs.values()) == 1, (name, runs)


def test_group_suffix_as_loadgroup_reads_it():
    assert grouped_nodeid("test/test_faults.py::t") == f"test/test_faults.py::t@{ROS_GROUP}"
    assert grouped_nodeid("test/test_cli.py::t[a@b]") == \
        "test/test_cli.py::t[a@b]@test/test_cli.py"
    assert grouped_nodeid("test/test_cli.py::t@mine") == "test/test_cli.py::t@mine"   # kept
    assert pytest_xdist_make_scheduler(_config("loadscope"), None) is None


class Item:
    """A stand-in for a collected test item: its markers by name."""

    def __init__(self, nodeid, *marks):
        self.nodeid, self.path = nodeid, Path(nodeid.split("::")[0])
        self.name = self.originalname = nodeid.split("::")[1]
        self.marks = {m: getattr(pytest.mark, m) for m in marks}

    def get_closest_marker(self, name):
        return self.marks.get(name)

    def add_marker(self, mark):
        self.marks[mark.name] = mark


def test_marks_by_file_fast_tier_and_ros_order():
    items = [Item("test/test_lumped.py::a"), Item("test/test_cli.py::b", "slow"),
             Item("test/test_vehicle_kane.py::c"), Item("test/test_ros_nodes.py::d")]
    assert "test_vehicle_kane.py" in SLOW_FILES and "test_ros_nodes.py" in ROS_FILES
    pytest_collection_modifyitems(None, items)
    assert [i.nodeid.split("::")[1] for i in items] == ["d", "b", "c", "a"]
    marks = {i.nodeid.split("::")[1]: set(i.marks) - {"xdist_group"} for i in items}
    assert marks == {"a": {"fast"}, "b": {"slow"}, "c": {"slow"}, "d": {"ros"}}
    assert items[0].marks["xdist_group"].args == (ROS_GROUP,)


def test_a_ros_test_outside_the_ros_files_is_refused():
    with pytest.raises(pytest.UsageError, match="test_lumped.py::a: marked ros outside"):
        pytest_collection_modifyitems(None, [Item("test/test_lumped.py::a", "ros")])


def test_every_listed_file_and_test_exists():
    """A renamed file or test would silently leave its list (and the tier it marks)."""
    here = Path(__file__).parent
    for name in ROS_FILES | SLOW_FILES | FAULT_FILES:
        assert (here / name).is_file(), name
    for entry in SLOW_TESTS:
        name, function = entry.split("::")
        assert f"def {function}(" in (here / name).read_text(encoding="utf-8"), entry
