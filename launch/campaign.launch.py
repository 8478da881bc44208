"""ros2 launch motoflex_ros campaign.launch.py [components:=a,b] [out:=bags/NAME] [seed:=N]
[noise:=SIGMA] [namespace:=/rig_a]: the same node graph as ``motoflex campaign`` (plain
``launch`` API); with a namespace every node and topic runs under it (two rigs in one domain).

Each node is started as its ``ros2 run`` executable with a parameters file written from
:func:`motoflex_ros.launcher.campaign_graph.campaign_specs`, so both ways run identical graphs. The
domain id is the caller's (set ROS_DOMAIN_ID yourself); each node keeps DDS on loopback unless
MOTOFLEX_DDS=network or a Fast DDS profile of your own; the launch ends when the load actuator
has played every protocol (and the vehicle simulator is done). No launcher judges the run, so
its folder gets no status.json: ``motoflex report`` and ``replay`` need ``--allow-incomplete``.
"""
import shutil
import sys
import tempfile
from pathlib import Path

import yaml
from launch.actions import (
    DeclareLaunchArgument,
    EmitEvent,
    ExecuteProcess,
    OpaqueFunction,
    RegisterEventHandler,
)
from launch.event_handlers import OnProcessExit
from launch.events import Shutdown
from launch.substitutions import LaunchConfiguration

from launch import LaunchDescription

ARGUMENTS = {"components": "frame,front_assembly,swingarm", "out": "bags/campaign",
             "seed": "0", "noise": "-1", "namespace": "/"}


def _executable(name):
    """The node's installed executable (colcon: lib/motoflex_ros), else ``python -m``."""
    found = shutil.which(name)
    for prefix in (Path(sys.prefix), Path(__file__).resolve().parents[3]):
        candidate = prefix / "lib" / "motoflex_ros" / name
        if candidate.is_file():
            found = str(candidate)
    return [found] if found else [sys.executable, "-m", f"motoflex_ros.nodes.{name}"]


def _graph(context):
    from motoflex_ros.launcher.campaign_graph import campaign_specs
    from motoflex_ros.launcher.graph import namespace_args, node_key
    value = {k: LaunchConfiguration(k).perform(context) for k in ARGUMENTS}
    noise = float(value["noise"])
    specs = campaign_specs(value["components"].split(","), value["out"],
                           None if noise < 0 else noise, int(value["seed"]))
    params_dir = Path(tempfile.mkdtemp(prefix="motoflex_launch_"))
    actions, names = [], []
    for spec in specs:
        params = {k: list(v) if isinstance(v, tuple) else v for k, v in spec.params.items()}
        path = params_dir / f"{spec.name}.yaml"
        path.write_text(yaml.safe_dump(
            {node_key(value["namespace"], spec.name): {"ros__parameters": params}}))
        actions.append(ExecuteProcess(cmd=[*_executable(spec.name), "--ros-args", "-r",
                                           f"__node:={spec.name}",
                                           *namespace_args(value["namespace"]),
                                           "--params-file", str(path)],
                                      name=spec.name, output="screen", sigterm_timeout="10"))
        names.append(spec.name)
    # ExecuteProcess.name is a list of substitutions (launch 3.x), never equal to a str: the
    # process that ends the launch is found by the names kept here
    last = "vehicle_simulator" if "vehicle_simulator" in names else "load_actuator"
    actions.append(RegisterEventHandler(OnProcessExit(
        target_action=actions[names.index(last)],
        on_exit=[EmitEvent(event=Shutdown(reason="campaign done"))])))
    return actions


def generate_launch_description():
    """The campaign graph; arguments components, out, seed, noise."""
    return LaunchDescription(
        [DeclareLaunchArgument(k, default_value=v) for k, v in ARGUMENTS.items()]
        + [OpaqueFunction(function=_graph)])
