"""The "road_load" and "vehicle_load" variants: hinges from bench tests loaded as the vehicle
loads the component (beyond the paper; the tests are :mod:`motoflex_ros.bench.load_tests`).

- road_load: the lateral force (or the protocol's ``road_load`` direction) at the tyre contact
  point of the vehicle's static configuration (or the protocol's point), through a rigid lever
  to the loaded end: the front tyre's for the frame and the front assembly, the rear tyre's for
  the swingarm. Upright and at rest the contact point lies a rolling radius below the wheel
  centre.
- vehicle_load: the load is the direction of the wrench the component carries in the wobble
  (or another mode) of the flexible motorcycle with that component flexible, at a chosen speed
  (:mod:`motoflex_ros.study.vehicle_load`).

Each gives {l, beta, b, k, c} under its name in a copy of the identification results, which
:func:`motoflex_ros.study.identified_variants.build_variant` turns into a single hinge as the
static one.
"""
import numpy as np

from motoflex_ros.bench.load_tests import lever_wrench, load_test
from motoflex_ros.bench.offline_campaign import setup_campaign
from motoflex_ros.errors import ModelError
from motoflex_ros.identify.results import ResultsFile
from motoflex_ros.study.vehicle_load import mode_wrench
from motoflex_ros.units import kmh_to_ms
from motoflex_ros.vehicle import lumped

__all__ = ["ROAD_WHEEL", "VEHICLE_LOAD_SPEED", "contact_point", "road_load_tests",
           "vehicle_load_tests", "with_load_tests"]

ROAD_WHEEL = {"frame": "front", "front_assembly": "front", "swingarm": "rear"}
"""The tyre whose road load each component carries."""
VEHICLE_LOAD_SPEED = float(kmh_to_ms(100.0))
"""Default speed [m/s] of the mode whose wrench loads the vehicle_load test (100 km/h)."""


def contact_point(vehicle, component):
    """The tyre contact point [m] (vehicle frame) of the wheel ``component`` carries, in the
    static configuration: a rolling radius below the wheel centre."""
    name = ROAD_WHEEL[component]
    hits = [w for w in vehicle.wheels if w.name == name]
    if not hits:
        raise ModelError(f"vehicle '{vehicle.name}' has no wheel '{name}' (the road load of "
                         f"'{component}')")
    wheel = hits[0]
    return np.asarray(wheel.centre, float) - np.array([0.0, 0.0, wheel.radius])


def _setup(component, setups):
    if setups and component.name in setups:
        return setups[component.name]
    return setup_campaign(component)


def road_load_tests(vehicle, components, names, setups=None, seed=0):
    """{component: LoadTestResult} of the road_load test of each component in ``names``.

    ``components``: {name: structures Component} placed in ``vehicle``; ``setups`` optional
    {name: CampaignSetup} (default: the component's shipped protocol)."""
    out = {}
    for name in names:
        component = components[name]
        setup = _setup(component, setups)
        spec = setup.protocol.road_load
        site = lumped.site_of(component)
        point = (np.asarray(spec.point_m, float) if spec.point_m is not None
                 else contact_point(vehicle, name) - site.origin)
        out[name] = load_test(setup, lever_wrench(site.q0, point, spec.direction),
                              "road_load", spec.force_n, seed)
    return out


def vehicle_load_tests(flexible, components, names, speed=VEHICLE_LOAD_SPEED, mode="wobble",
                       setups=None, seed=0):
    """{component: (LoadTestResult, ModeWrench)} of the vehicle_load test of each component.

    ``flexible``: {component: LinearVehicle of the flexible motorcycle with that component
    flexible}; the wrench is taken in ``mode`` at ``speed`` [m/s] and scaled to a unit force.
    """
    out = {}
    for name in names:
        site = lumped.site_of(components[name])
        carried = mode_wrench(flexible[name], name, speed, mode, float(np.linalg.norm(site.q0)))
        setup = _setup(components[name], setups)
        out[name] = (load_test(setup, carried.direction, "vehicle_load", seed=seed), carried)
    return out


def with_load_tests(identified, results):
    """A copy of the identification results with each LoadTestResult's model under its name.

    ``results``: {component: LoadTestResult or (LoadTestResult, ...)}."""
    out = {name: dict(value) for name, value in identified.items()}
    if isinstance(identified, ResultsFile):
        out = ResultsFile(out, identified.source)
    for name, result in results.items():
        test = result[0] if isinstance(result, tuple) else result
        out[name][test.name] = test.to_dict()
    return out
