"""Markers by file and the groups ./test.sh spreads over two pytest-xdist workers.

Markers (registered in pyproject.toml) are given here per file, not one by one in the files:

- ``ros``: the files in ROS_FILES, whose every test starts ROS 2 node processes. A test
  marked ``ros`` in any other file is refused at collection (it would run beside the graph
  tests instead of after them): such a test goes into a ROS file of its own.
- ``slow``: the files in SLOW_FILES, the tests in SLOW_TESTS and the tests marked ``slow``
  one by one (over a few seconds of an idle core).
- ``fast``: every test that is neither ``ros`` nor ``slow``: ``./test.sh -m fast`` is the
  everyday tier (docs/testing.md).

Groups (``./test.sh`` runs ``-n 2 --dist loadgroup``): every ROS file in one group,
``ros-graph``, so the graph tests run one after the other on one worker, in file order (the
fault tests, which hold a run's reaction time, never meet a second graph; each test also has
a ROS domain of its own); every other file is a group of its own, so a module fixture (the
accuracy study's verb run, the Kane oracle) is computed once. The items are put in order
ROS group first, then files holding slow tests, then the rest (the longest units start
first, the short ones fill in at the end). With ``-n 0`` (or plain ``pytest``) everything runs
in one process and the groups do nothing.

The groups are ``xdist_group`` marks, and one public scheduler hook puts them into effect:
xdist 3.8 suffixes the group to ``item._nodeid``, which pytest 9.2 no longer reads (a node's
id lives in ``Node._id``), so the collection the workers send carries no groups. The
scheduler below is xdist's own LoadGroupScheduling, given the collection with each test's
group suffixed as xdist documents it (``nodeid@group``), computed from the file by the same
function as the marks; where xdist did suffix it (an xdist that works with the pytest in
use), the suffix is kept.

Mesh reductions are cached on disk (structures/reduction_cache.py): a test run keeps its own
cache in a temporary folder (made by the first pytest process, inherited by the xdist workers,
removed at exit) unless MOTOFLEX_CACHE_DIR is set, so no run reads what another run or the
user's ~/.cache left. MOTOFLEX_TEST_SHARED, made the same way, holds what several test files
read of the example run, made once per run (test/example_runs.py).
"""
import atexit
import os
import shutil
import tempfile

import pytest

ROS_GROUP = "ros-graph"

# Files whose every test starts ROS 2 node processes (marked ros, grouped in ROS_GROUP).
ROS_FILES = {
    "test_bad_inputs_nodes.py", "test_campaign_bag.py", "test_campaign_graph.py",
    "test_campaign_launch_run.py", "test_campaign_namespaces.py", "test_docs_ros.py",
    "test_faults.py", "test_measured_live.py", "test_mesh_chain_graph.py",
    "test_node_interfaces.py", "test_replay_rate.py", "test_ros_network_nodes.py",
    "test_ros_nodes.py", "test_run_trust.py", "test_transport.py",
}
# Files whose every test is slow (a module fixture of ten seconds or more, or most tests over a
# few seconds): the Kane oracle's symbolic derivation, the gmsh and solid-frame meshes, the
# flexible motorcycle and the per-body syntheses, the accuracy study's verb run, the noise and
# decay seeds, the measured bags, the rerun recordings, the 60 bad-input commands (a child
# each, for the hang guard); and the ROS files that start whole campaigns. Measured with
# ``./test.sh -m fast --durations=30`` (docs/testing.md).
SLOW_FILES = {
    "test_bad_inputs.py", "test_campaign_bag.py", "test_campaign_graph.py",
    "test_campaign_launch_run.py", "test_campaign_namespaces.py", "test_decomposed.py",
    "test_docs_ros.py", "test_faults.py", "test_flexible_bodies_bench.py",
    "test_flexible_motorcycle.py", "test_frame_mesh.py", "test_frame_mesh_vehicle.py",
    "test_identify_decay_noise.py", "test_measured_bag.py", "test_measured_identify.py",
    "test_measured_live.py", "test_mesh_chain_graph.py", "test_mesh_gmsh.py",
    "test_principal_noise.py", "test_rerun_bag.py", "test_rerun_blueprint.py",
    "test_run_trust.py", "test_study_accuracy.py", "test_study_sensitivity_published.py",
    "test_vehicle_kane.py",
}
# Single slow tests in otherwise fast files (``file::function``, every parameter of it).
SLOW_TESTS = {
    "test_bag_integrity.py::test_flipped_bit_fails_every_read_naming_chunk_and_offset",
    "test_bag_integrity.py::test_repair_of_a_finished_bag_writes_a_new_marked_bag",
    "test_bag_integrity.py::test_report_refuses_a_run_without_its_identification",
    "test_bench_campaign.py::test_same_seed_same_numbers_other_seed_other_numbers",
    "test_docs.py::test_getting_started_example_runs",
    "test_hostile_inputs.py::test_real_failed_replay_keeps_its_logs_beside_its_output",
    "test_report_summary.py::test_summary_names_the_outcome_handed_over_before_status_json",
    "test_transport.py::test_campaign_on_the_plain_path_identifies_as_the_ctypes_path",
}
# The fault injection into running campaigns (issue 13): ./test.sh -m faults runs it alone.
FAULT_FILES = {"test_faults.py"}

for _variable, _prefix in (("MOTOFLEX_CACHE_DIR", "motoflex-cache-"),
                           ("MOTOFLEX_TEST_SHARED", "motoflex-test-shared-")):
    if _variable not in os.environ:   # the first process of the run: the workers inherit it
        _folder = tempfile.mkdtemp(prefix=_prefix)
        os.environ[_variable] = _folder
        atexit.register(shutil.rmtree, _folder, ignore_errors=True)


def file_group(path):
    """The xdist group of a test file (its path relative to the rootdir, ``/``-separated)."""
    return ROS_GROUP if path.rsplit("/", 1)[-1] in ROS_FILES else path


def grouped_nodeid(nodeid):
    """``nodeid@group`` as ``--dist loadgroup`` reads it; a suffix already there is kept."""
    if nodeid.rfind("@") > nodeid.rfind("]"):
        return nodeid
    return f"{nodeid}@{file_group(nodeid.split('::', 1)[0])}"


@pytest.hookimpl(optionalhook=True)
def pytest_xdist_make_scheduler(config, log):
    """Xdist's LoadGroupScheduling on the collection with the groups suffixed (see above)."""
    if config.getvalue("dist") != "loadgroup":
        return None
    from xdist.scheduler import LoadGroupScheduling

    class FileGroupScheduling(LoadGroupScheduling):
        def add_node_collection(self, node, collection):
            super().add_node_collection(node, [grouped_nodeid(i) for i in collection])

    return FileGroupScheduling(config, log)


def _file_marks(item):
    name = item.path.name
    marks = [m for m, files in (("ros", ROS_FILES), ("slow", SLOW_FILES),
                                ("faults", FAULT_FILES)) if name in files]
    if f"{name}::{getattr(item, 'originalname', item.name)}" in SLOW_TESTS:
        marks.append("slow")
    return [getattr(pytest.mark, m) for m in marks]


def _order(item, slow_files):
    path = item.nodeid.split("::", 1)[0]
    return 0 if file_group(path) == ROS_GROUP else 1 if path in slow_files else 2


@pytest.hookimpl(tryfirst=True)
def pytest_collection_modifyitems(config, items):
    """Marks and group by file (module docstring); refuses a ``ros`` test outside ROS_FILES."""
    for item in items:
        path = item.nodeid.split("::", 1)[0]
        for mark in _file_marks(item):
            item.add_marker(mark)
        if item.get_closest_marker("ros") and item.path.name not in ROS_FILES:
            raise pytest.UsageError(f"{item.nodeid}: marked ros outside ROS_FILES of "
                                    "test/conftest.py (it would run beside the graph tests); "
                                    "move it into a ROS file")
        if not (item.get_closest_marker("ros") or item.get_closest_marker("slow")):
            item.add_marker(pytest.mark.fast)
        item.add_marker(pytest.mark.xdist_group(file_group(path)))
    slow_files = {i.nodeid.split("::", 1)[0] for i in items if i.get_closest_marker("slow")}
    items.sort(key=lambda item: _order(item, slow_files))
