"""Each node's declared TOPICS are the endpoints it creates (issue 24, point 8).

``--help`` and docs/ros-interfaces.md are written from the declarations; here every node is
constructed in-process (its own ROS domain, no spinning) and the publishers and subscriptions
the graph then shows for it are compared with what it declares.
"""
import importlib
import re
import subprocess
import sys
from pathlib import Path

import pytest

pytest.importorskip("rclpy")
import rclpy  # noqa: E402

from motoflex_ros.launcher.domain import DomainLock  # noqa: E402
from motoflex_ros.nodes import NODE_CLASSES  # noqa: E402
from motoflex_ros.nodes.interfaces import expand  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "bags" / "example"
COMPONENT = "swingarm"
RCLPY_OWN = {"/rosout", "/parameter_events"}

# per node: ROS arguments, the components its {c} stands for, the conditions that hold
CASES = {
    "sim_clock": ([], (), ()),
    "load_actuator": ([f"components:=[{COMPONENT}]"], (COMPONENT,), ()),
    "component_simulator": ([f"components:=[{COMPONENT}]"], (COMPONENT,), ()),
    "displacement_sensor": ([f"components:=[{COMPONENT}]"], (COMPONENT,), ()),
    "identification": ([f"components:=[{COMPONENT}]"], (COMPONENT,), ("mode virtual",)),
    "vehicle_simulator": ([], (), ("result_file ''",)),
    "recorder": (["bag:={tmp}/bag"], (), ()),
    "bag_replay": ([f"bag:={EXAMPLE}"], (), ()),
}


def _endpoints(node):
    name, namespace = node.get_name(), node.get_namespace()
    found = {("pub", t): types[0]
             for t, types in node.get_publisher_names_and_types_by_node(name, namespace)}
    found.update({("sub", t): types[0]
                  for t, types in node.get_subscriber_names_and_types_by_node(name, namespace)})
    return {k: v for k, v in found.items() if k[1] not in RCLPY_OWN}


@pytest.fixture(scope="module")
def domain():
    with DomainLock() as lock:
        yield lock.domain_id


def test_every_node_has_a_case():
    assert set(CASES) == set(NODE_CLASSES)


@pytest.mark.parametrize("name", sorted(CASES))
def test_declared_topics_are_the_nodes_endpoints(name, domain, tmp_path):
    params, components, conditions = CASES[name]
    node_class = getattr(importlib.import_module(f"motoflex_ros.nodes.{name}"),
                         NODE_CLASSES[name])
    args = ["x", "--ros-args", "-r", f"__node:={name}"]
    for p in params:
        args += ["-p", p.format(tmp=tmp_path)]
    rclpy.init(args=args, domain_id=domain)
    try:
        node = node_class()
        try:
            found = _endpoints(node)
        finally:
            node.destroy_node()
    finally:
        rclpy.shutdown()
    declared = expand(node_class.TOPICS, components, conditions)
    if name == "bag_replay":   # and every topic of the bag
        from motoflex_ros.record.mcap_bag import bag_info
        for topic in bag_info(EXAMPLE).topics:
            if not topic.name.startswith(("/rig/", "/tf")):
                declared[("pub", topic.name)] = topic.type
    assert found == declared


def test_help_lists_topics_and_parameters():
    run = subprocess.run([sys.executable, "-m", "motoflex_ros.nodes.displacement_sensor",
                          "--help"], capture_output=True, text=True, timeout=60)
    assert run.returncode == 0, run.stderr
    text = run.stdout
    assert "publishes:" in text and "subscribes:" in text
    assert "/bench/{c}/markers/measured  geometry_msgs/msg/PoseArray" in text
    assert "/bench/{c}/markers/true  geometry_msgs/msg/PoseArray" in text
    assert re.search(r"^  noise +float in \[-1, 0\.001\]", text, re.M)


def test_docs_page_is_written_from_the_declarations():
    run = subprocess.run([sys.executable, str(ROOT / "tools" / "write_ros_interfaces.py"),
                          "--check"], capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr

