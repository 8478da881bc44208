"""How ./test.sh spreads the suite over two pytest-xdist workers (``-n 2 --dist loadscope``).

The files whose every test starts ROS 2 node processes (module marker ``ros``: the campaign,
fault, live and node tests) form one scope, so they run one after the other on one worker: the
fault tests, which hold a run's reaction time, never meet a second graph of their own kind
(each test also has a ROS domain of its own, so parallel graphs cannot cross). Every other file
is a scope of its own, so a module fixture (the accuracy study's verb run, the Kane oracle) is
computed once. The two cores then share the ROS scope (lock-step nodes, about 1.4 cores) and the
numerical tests (one core each). With ``./test.sh -n 0`` (or plain ``pytest``) everything runs in
one process and the scopes do nothing.

The scheduler is given here, not by ``xdist_group`` markers: pytest 9.2 reads a node's id from
``Node._id``, so xdist 3.8's ``--dist loadgroup`` (which renames ``item._nodeid``) no longer
groups anything.

Mesh reductions are cached on disk (structures/reduction_cache.py): each test process keeps
its own cache in a temporary folder (removed at exit) unless MOTOFLEX_CACHE_DIR is set, so no
run reads what another run or the user's ~/.cache left.
"""
import atexit
import os
import shutil
import tempfile
from collections import OrderedDict
from pathlib import Path

import pytest

ROS_SCOPE = "ros-graph"
HERE = Path(__file__).parent

if "MOTOFLEX_CACHE_DIR" not in os.environ:
    _CACHE = tempfile.mkdtemp(prefix="motoflex-cache-")
    os.environ["MOTOFLEX_CACHE_DIR"] = _CACHE
    atexit.register(shutil.rmtree, _CACHE, ignore_errors=True)


def ros_files(rootpath):
    """Test files (rootdir-relative ids) whose module marker (``pytestmark``) is ``ros``, read
    from their text: the controller, which schedules, collects nothing."""
    return {p.relative_to(rootpath).as_posix() for p in sorted(HERE.glob("test_*.py"))
            if any(line.startswith("pytestmark") and "pytest.mark.ros" in line
                   for line in p.read_text(encoding="utf-8").splitlines())}


@pytest.hookimpl(optionalhook=True)
def pytest_xdist_make_scheduler(config, log):
    from xdist.scheduler import LoadScopeScheduling

    ros = ros_files(config.rootpath)

    class RosFirst(OrderedDict):
        """The work queue with the ROS scope at its head: the longest unit starts first."""

        def __setitem__(self, scope, tests):
            super().__setitem__(scope, tests)
            if scope == ROS_SCOPE:
                self.move_to_end(scope, last=False)

    class RosTogether(LoadScopeScheduling):
        def __init__(self, config, log=None):
            super().__init__(config, log)
            self.workqueue = RosFirst()

        def _split_scope(self, nodeid):
            path = nodeid.split("::", 1)[0]
            return ROS_SCOPE if path in ros else path

    return RosTogether(config, log)


def pytest_collection_modifyitems(config, items):
    """The text scan above agrees with the modules' real markers (a ``pytestmark`` written
    another way would otherwise escape the ROS scope)."""
    ros = ros_files(config.rootpath)
    for item in items:
        marks = getattr(item.module, "pytestmark", [])
        marked = any(m.name == "ros" for m in (marks if isinstance(marks, list) else [marks]))
        if marked != (item.nodeid.split("::", 1)[0] in ros):
            raise pytest.UsageError(f"{item.nodeid}: module marker ros and the ROS scope "
                                    "of test/conftest.py disagree")
