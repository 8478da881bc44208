"""The documentation's examples that start ROS 2 nodes, run as written: the getting-started
page's (``motoflex replay``) and the real-rig page's bench started by hand. With the other ROS
graph tests (module marker ``ros``), so they never meet a fault test's graph. The rest of the
documentation tests: ``test_docs.py``."""
import json
import os
import shlex
import signal
import subprocess
import sys
import time

import pytest
from doc_pages import DOCS, commands, example_folder, examples, run_example, section_blocks

from motoflex_ros.launcher.domain import DomainLock
from motoflex_ros.launcher.graph import ros_env

HAND_STARTED = "## The bench started by hand"
IDENTIFIED_K = 1.04648e6   # the frame's k the page quotes [N m/rad]


@pytest.mark.parametrize("example", examples(ros=True), ids=lambda e: f"line{e[1]}")
def test_getting_started_ros_example_runs(example, tmp_path, monkeypatch):
    text, line = example
    monkeypatch.setenv("ROS_LOG_DIR", str(tmp_path / "ros_log"))
    monkeypatch.delenv("ROS_DOMAIN_ID", raising=False)   # the verb takes a free domain itself
    done = run_example(text, example_folder(tmp_path))
    assert done.returncode == 0, f"getting-started.md:{line}\n{text}\n{done.stderr[-2000:]}"


def _wait(process, timeout):
    try:
        return process.wait(timeout)
    except subprocess.TimeoutExpired:
        return None


def test_bench_started_by_hand_as_documented(tmp_path):
    """The page's commands, each its own process, the recorder with the page's parameters
    file: the actuator ends by itself, the frame's k is the one quoted, three nodes and the
    identification keep running until SIGINT (then exit 0, no message lost), and replay
    refuses the bag that has no status.json."""
    block, = section_blocks(DOCS / "real-rig.md", HAND_STARTED, "console")
    params, = section_blocks(DOCS / "real-rig.md", HAND_STARTED, "yaml")
    (tmp_path / "recorder.yaml").write_text(params)
    (tmp_path / "bags").mkdir()
    scripts = os.path.dirname(sys.executable)
    with DomainLock() as lock:
        env = ros_env(lock.domain_id, tmp_path / "log")
        env["PATH"] = scripts + os.pathsep + env["PATH"]
        nodes = {}
        try:
            for command in commands(block):
                argv = shlex.split(command)
                with open(tmp_path / f"{argv[0]}.log", "w") as log:   # the child keeps it
                    nodes[argv[0]] = subprocess.Popen(argv, cwd=tmp_path, env=env,
                                                      stdout=log, stderr=subprocess.STDOUT)
            actuator_log = tmp_path / "load_actuator.log"
            assert _wait(nodes["load_actuator"], 180) == 0, actuator_log.read_text()
            result = tmp_path / "bags" / "by_hand_frame.json"
            deadline = time.monotonic() + 30
            while not result.is_file() and time.monotonic() < deadline:
                time.sleep(0.2)
            k = json.loads(result.read_text())["frame"]["static"]["k"]
            assert k == pytest.approx(IDENTIFIED_K, rel=5e-6)
            time.sleep(1.0)
            running = {name for name, p in nodes.items() if p.poll() is None}
            assert running == {"recorder", "component_simulator", "displacement_sensor",
                               "identification"}
            for name in running:
                nodes[name].send_signal(signal.SIGINT)
            codes = {name: _wait(nodes[name], 30) for name in running}
            assert codes == dict.fromkeys(running, 0)
        finally:
            for process in nodes.values():
                if process.poll() is None:
                    process.kill()
                    process.wait()
    refused = subprocess.run([os.path.join(scripts, "motoflex"), "replay", "bags/by_hand"],
                             cwd=tmp_path, capture_output=True, text=True, timeout=60)
    assert refused.returncode != 0
    assert "no status.json" in refused.stderr and "--allow-incomplete" in refused.stderr
