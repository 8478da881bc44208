"""The bench campaign as a ROS 2 graph: which nodes, with which parameters, and its outcome.

Nodes: load_actuator (paces), component_simulator, displacement_sensor, identification, the
recorder and, when all three motorcycle components are in, the vehicle_simulator (the lumped
'static' motorcycle of the identified values), each a separate process on a private domain.
The identification node writes the same result file as ``motoflex identify --out``; the
recorder writes the rosbag2 bag.
"""
import json
import time
from dataclasses import dataclass
from pathlib import Path

from diagnostic_msgs.msg import DiagnosticArray

from motoflex_ros.config import MOTORCYCLE_COMPONENTS
from motoflex_ros.files import atomic_write_text
from motoflex_ros.launcher.graph import NodeSpec
from motoflex_ros.launcher.run import run_graph, work_folder
from motoflex_ros.launcher.run_failures import RunFailed
from motoflex_ros.launcher.status import staged
from motoflex_ros.nodes.result_messages import IDENTIFIED_UNITS
from motoflex_ros.record.mcap_bag import check_new_bag_dir
from motoflex_ros.record.tf_bag import TF_LIVE, TF_STATIC_LIVE
from motoflex_ros.vehicle.mode_names import MODE_NAMES

__all__ = ["CampaignOutcome", "campaign_specs", "campaign_topics", "run_campaign_graph",
           "bench_components",
           "planned_run", "campaign_inputs", "RESULT_FILE", "VEHICLE", "VEHICLE_COMPONENTS",
           "VEHICLE_VARIANT"]

RESULT_FILE = "identification.json"
BENCH_LEAVES = ("load", "phase", "phase_values", "markers/true", "markers/measured", "pose",
                "structure")


@dataclass(frozen=True)
class CampaignOutcome:
    """Results {component: identify-format dict}, the bag, the run's wall time [s], and the
    vehicle's modes {weave|wobble|capsize: {speeds_kmh, real, frequency_hz}} (or {})."""

    results: dict
    bag: Path
    result_file: Path
    wall_s: float
    domain_id: int
    vehicle: dict
    inputs: dict = None
    """{absolute path: SHA-256} of every input file the run read (pinned for the run)."""


VEHICLE_TOPICS = ("/vehicle/eigenvalues", "/vehicle/joint_states", "/vehicle/bodies",
                  "/vehicle/joint_axes", "/vehicle/geometry", "/vehicle/modes/speed_kmh",
                  *(f"/vehicle/modes/{m}/{q}" for m in MODE_NAMES for q in ("frequency_hz",
                                                                      "real_part")))

VEHICLE_COMPONENTS = MOTORCYCLE_COMPONENTS
VEHICLE = "touring"
"""The vehicle (shipped name) the campaign's vehicle_simulator builds."""
VEHICLE_VARIANT = "static"
"""The lumped variant (Sect. 5.2) the campaign's vehicle_simulator builds of the identified
values; the campaign prints its weave and wobble and the report shows them."""


def with_vehicle(components):
    """Does the campaign include the vehicle (all three shipped motorcycle components, by
    name: a component from a YAML file is tested on the bench only)?"""
    return set(VEHICLE_COMPONENTS) <= set(components)


def bench_components(components):
    """(names, specs) of the campaign's components: the name each goes by (its topics are
    /bench/<name>/...) and what the nodes load (a shipped name, or a YAML file's absolute
    path); ConfigError when two have one name."""
    from motoflex_ros.errors import ConfigError
    from motoflex_ros.formats.component_file import component_name
    names, specs = [], []
    for given in components:
        name = component_name(given)
        if name in names:
            raise ConfigError("command line", "--component", f"two components are called "
                                                              f"'{name}' ({given})")
        path = Path(given)
        names.append(name)
        specs.append(str(path.resolve()) if path.suffix in (".yaml", ".yml") or path.exists()
                     else given)
    return names, specs


def campaign_topics(components):
    """Every topic the campaign records."""
    vehicle = list(VEHICLE_TOPICS) if with_vehicle(components) else []
    return ["/clock", "/identification/results", f"/{TF_STATIC_LIVE}", f"/{TF_LIVE}"] + [
        f"/bench/{c}/{leaf}" for c in components for leaf in BENCH_LEAVES] + \
        identified_topics(components) + vehicle


def identified_topics(components):
    """The numeric identification topics /identification/<c>/{k, l, beta}."""
    return [f"/identification/{c}/{q}" for c in components for q in IDENTIFIED_UNITS]


def campaign_specs(components, bag, noise=None, seed=0, protocol=None, result_file=None):
    """NodeSpecs of the campaign graph recording to ``bag`` (a directory that must not exist);
    the identification node writes ``result_file`` (default ``bag``/identification.json)."""
    names, specs = bench_components(components)
    bench = {"components": specs, "seed": int(seed),
             "noise": -1.0 if noise is None else float(noise), "protocol": protocol or ""}
    workers = ["component_simulator", "displacement_sensor", "identification", "recorder"]
    vehicle = ([NodeSpec("vehicle_simulator", {"components": list(VEHICLE_COMPONENTS),
                                               "vehicle": VEHICLE,
                                               "variant": VEHICLE_VARIANT})]
               if with_vehicle(components) else [])
    return vehicle + [
        NodeSpec("load_actuator", {**bench, "wait_for": workers}),
        NodeSpec("component_simulator", dict(bench)),
        NodeSpec("displacement_sensor", dict(bench)),
        NodeSpec("identification", {**bench,
                                    "result_file": str(result_file or Path(bag) / RESULT_FILE)}),
        NodeSpec("recorder", {"bag": str(bag), "topics": campaign_topics(names),
                              "late_topics": ["/identification/results", *VEHICLE_TOPICS,
                                              *identified_topics(names)]}),
    ]


def planned_run(components, noise=None, protocol=None):
    """(planned simulated time of the bench [s]: the components one after the other, each
    PAUSE_S after the previous one (tests may settle sooner), number of bench tests over all
    components)."""
    from motoflex_ros.bench.actuator import PAUSE_S
    from motoflex_ros.bench.offline_campaign import setup_campaign
    from motoflex_ros.formats.component_file import load_component
    total, tests = 0.0, 0
    for name in components:
        plan = setup_campaign(load_component(name), protocol, noise).plan
        total += sum(t.max_samples / t.rate_hz for t in plan.tests) + PAUSE_S * len(plan.tests)
        tests += len(plan.tests)
    return total - PAUSE_S, tests


def campaign_inputs(components, noise=None, protocol=None):
    """(:func:`planned_run`'s (duration [s], tests), {absolute path: SHA-256} of every file
    the campaign's nodes read): each component, its protocol and the files they name, the
    vehicle when it runs or when a component's principal hinges take their metric from it (as
    the identification node's :func:`~motoflex_ros.nodes.bench_graph.campaign_setups` does);
    read here once, so that the nodes can be held to the same bytes."""
    from motoflex_ros.config import resolve_config
    from motoflex_ros.formats.component_file import load_components
    from motoflex_ros.input_pins import recording_inputs
    from motoflex_ros.study.identified_variants import carried_inertias
    from motoflex_ros.vehicle.model import load_vehicle
    with recording_inputs() as inputs:
        planned = planned_run(components, noise, protocol)
        carried_inertias(load_components(components))
        if with_vehicle(components):
            load_vehicle(resolve_config("vehicles", VEHICLE))
    return planned, inputs


def run_campaign_graph(components, bag, noise=None, seed=0, protocol=None, progress=False,
                       work_dir=None, namespace=None):
    """Run the campaign through the graph; returns a :class:`CampaignOutcome`. The results
    file gets its name only once every node finished cleanly (until then it is staged).
    ``namespace`` ('/rig_a') puts every node and topic under it (two rigs in one domain)."""
    bag = check_new_bag_dir(bag)
    result_file = bag / RESULT_FILE
    specs = campaign_specs(components, bag, noise, seed, protocol, staged(result_file))
    start = time.monotonic()
    (duration_s, tests), inputs = campaign_inputs(components, noise, protocol)
    finishers = ["vehicle_simulator"] if with_vehicle(components) else []
    # parameters and logs in a temporary folder, removed at the end; on a failure the logs
    # are kept in the bag's folder (work_folder)
    with work_folder("motoflex_campaign_", work_dir, keep_logs_in=bag) as work_dir:
        run = run_graph(specs, "load_actuator", duration_s, tests_total=tests,
                        work_dir=work_dir, progress=progress, finishers=finishers,
                        collect=[("vehicle/eigenvalues", DiagnosticArray)],
                        namespace=namespace, pins=inputs)
        if not staged(result_file).is_file():
            raise RunFailed(f"the identification node wrote no {RESULT_FILE} in {bag}; its "
                            f"log: {work_dir / 'log' / 'identification.log'}")
    staged(result_file).replace(result_file)
    names, specs = bench_components(components)
    files = {n: s for n, s, given in zip(names, specs, components) if s != given or
             Path(s).is_file()}
    if files:   # what draws them in the rerun recording and the report
        from motoflex_ros.record.rerun_bag import COMPONENTS_FILE
        atomic_write_text(bag / COMPONENTS_FILE, json.dumps(files, indent=1) + "\n")
    results = json.loads(result_file.read_text())
    eig = run.collected["vehicle/eigenvalues"]
    vehicle = {s.name.split("/")[1]: {kv.key: json.loads(kv.value) for kv in s.values}
               for s in eig[-1].status} if eig else {}
    return CampaignOutcome(results, bag, result_file, time.monotonic() - start, run.domain_id,
                           vehicle, inputs)
