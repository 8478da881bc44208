"""The offline bench campaign: drives the four stage objects exactly as the ROS 2 graph does.

Per sample, in this order: ``LoadActuator.next_sample`` -> ``ComponentSimulator.step`` ->
``MarkerSensor.capture`` (noise drawn from the seeded generator) -> ``Identifier.add_load`` and
``Identifier.add_measurement`` for each delivered measurement; when the identifier reports a
harmonic test settled, ``LoadActuator.end_test``. At the end the sensor is flushed and the
readings are turned into the identified models. A graph that forwards the same samples in the
same order gives the same numbers.
"""
from dataclasses import dataclass, replace

import numpy as np

from motoflex_ros.bench.actuator import LoadActuator
from motoflex_ros.bench.clamped_modes import clamped_modes
from motoflex_ros.bench.plan import plan_campaign
from motoflex_ros.bench.protocols import load_protocol, protocol_for
from motoflex_ros.bench.response import ComponentSimulator
from motoflex_ros.bench.sensor import MAX_NOISE_M, MAX_SEED, MarkerSensor
from motoflex_ros.identify.identifier import Identifier
from motoflex_ros.identify.results import MODEL_TESTS, identify_component
from motoflex_ros.spatial import rotation_from_vector

__all__ = ["CampaignSetup", "CampaignRun", "setup_campaign", "make_stages", "run_campaign",
           "identify_components", "only_tests", "with_sensor", "measure_motion", "checked_noise",
           "checked_seed"]


@dataclass(frozen=True)
class CampaignSetup:
    """A component's reduced model, its modes, the planned protocol, the Component and the
    inertia the loaded end carries (a CarriedInertia for the principal hinges, or None)."""

    name: str
    reduced: object
    modes: object
    protocol: object
    plan: object
    component: object = None
    carried: object = None


@dataclass(frozen=True)
class CampaignRun:
    """Result of one campaign: the identification, the readings and the sample count."""

    identification: object
    readings: dict
    n_samples: int
    trace: dict = None


def setup_campaign(comp, protocol=None, noise_m=None, carried=None):
    """CampaignSetup of a built component ``comp`` (a structures Component, MeshComponent or
    SuperelementComponent; read from its file at the edge:
    :func:`motoflex_ros.formats.component_file.load_component`) with a protocol (name, file,
    Protocol or None for the component's shipped protocol); noise_m [m] overrides the sensor;
    ``carried`` the CarriedInertia of the principal hinges (None: they are not identified).
    """
    reduced = comp.clamped_reduced()
    if protocol is None:
        protocol = protocol_for(comp.name)
    elif isinstance(protocol, str):
        protocol = load_protocol(protocol)
    if noise_m is not None:
        protocol = replace(protocol, sensor=replace(protocol.sensor,
                                                    noise_m=checked_noise(noise_m)))
    modes = clamped_modes(reduced)
    return CampaignSetup(comp.name, reduced, modes, protocol,
                         plan_campaign(protocol, reduced, modes), comp, carried)


def checked_noise(noise_m, source="sensor noise override", key="noise_m"):
    """A sensor-noise override [m] (standard deviation per coordinate), checked to
    [0, MAX_NOISE_M] (:data:`motoflex_ros.bench.sensor.MAX_NOISE_M`, 1 mm)."""
    from motoflex_ros.config import number_text
    from motoflex_ros.errors import ConfigError
    value = float(noise_m)
    if not 0.0 <= value <= MAX_NOISE_M:
        raise ConfigError(source, key, f"sensor noise must be in [0, {MAX_NOISE_M:g}] m (the "
                                       f"bench's deformations are at most about a millimetre), "
                                       f"got {number_text(value)}")
    return value


def checked_seed(seed, source="seed", key="seed"):
    """A seed of the sensor noise: a whole number in [0, MAX_SEED] (numpy refuses negatives)."""
    from motoflex_ros.errors import ConfigError
    if isinstance(seed, bool) or not isinstance(seed, int) or not 0 <= seed <= MAX_SEED:
        raise ConfigError(source, key, f"seed must be a whole number in [0, {MAX_SEED}], "
                                       f"got {seed!r}")
    return seed


def with_sensor(setup, **changes):
    """The same setup with sensor settings changed (e.g. noise_m=0.0, resolution_m=0.0)."""
    protocol = replace(setup.protocol, sensor=replace(setup.protocol.sensor, **changes))
    return replace(setup, protocol=protocol)


def make_stages(setup, seed=0):
    """The four stage objects of a campaign: actuator, simulator, sensor, identifier."""
    q0 = setup.reduced.q0
    return (LoadActuator(setup.plan), ComponentSimulator(setup.reduced),
            MarkerSensor(setup.protocol.sensor, q0, seed),
            Identifier(q0, setup.protocol.harmonic))


def _deliver(identifier, actuator, measurements):
    for m in measurements:
        done = identifier.add_measurement(m)
        if done:
            actuator.end_test(done)


def measure_motion(setup, samples, motions, seed=0):
    """Readings of the sensor and identifier stages over a known load history and motion.

    ``samples``: the actuator's LoadSamples; ``motions`` (n, 6): the true loaded-end motion at
    each sample (displacement [m], rotation vector [rad]), e.g. one simulation replayed with
    many sensor-noise seeds. Returns what the campaign with that sensor ``seed`` measures
    (``Identifier.readings()``), without simulating the structure again.
    """
    q0 = np.asarray(setup.reduced.q0, float)
    sensor = MarkerSensor(setup.protocol.sensor, q0, seed)
    identifier = Identifier(q0, setup.protocol.harmonic)
    for sample, motion in zip(samples, motions):
        identifier.add_load(sample)
        for m in sensor.capture(sample.index, sample.t, q0 + motion[:3],
                                rotation_from_vector(motion[3:])):
            identifier.add_measurement(m)
    for m in sensor.flush():
        identifier.add_measurement(m)
    return identifier.readings()


def only_tests(setup, names):
    """The same setup with only the tests called ``names`` (e.g. ('static',)) in its plan."""
    tests = tuple(t for t in setup.plan.tests if t.name in names)
    return replace(setup, plan=replace(setup.plan, tests=tests))


def run_campaign(setup, seed=0, trace=False):
    """Run the campaign offline; ``trace`` keeps (t, force, true motion, test) arrays.

    The identification is made when the plan has the static, torsion and bending tests
    (otherwise ``identification`` is None and only the readings are returned).
    """
    actuator, simulator, sensor, identifier = make_stages(setup, seed)
    q0 = np.asarray(setup.reduced.q0, float)
    rows, n = [], 0
    while (sample := actuator.next_sample()) is not None:
        motion = simulator.step(sample)
        identifier.add_load(sample)
        position, rotation = q0 + motion[:3], rotation_from_vector(motion[3:])
        _deliver(identifier, actuator, sensor.capture(sample.index, sample.t, position,
                                                      rotation))
        if trace:
            rows.append((sample.t, sample.force, sample.test, motion.copy()))
        n += 1
    _deliver(identifier, actuator, sensor.flush())
    readings = identifier.readings()
    result = None
    if set(MODEL_TESTS) <= set(readings):
        result = identify_component(setup.name, readings, setup.modes, q0, setup.carried)
    table = None
    if trace:
        table = {"t": np.array([r[0] for r in rows]), "force": np.array([r[1] for r in rows]),
                 "test": [r[2] for r in rows], "motion": np.array([r[3] for r in rows])}
    return CampaignRun(result, readings, n, table)


def identify_components(components, protocol=None, noise_m=None, seed=0, progress=None,
                        carried=None):
    """Run the campaign of each (built) component; returns {name: (CampaignSetup, CampaignRun)}.
    ``progress`` (optional) is called with each component's name once it is done; ``carried``
    (optional) maps a component name to its CarriedInertia (the principal hinges' metric)."""
    out = {}
    carried = carried or {}
    for component in components:
        setup = setup_campaign(component, protocol, noise_m)
        setup = replace(setup, carried=carried.get(setup.name))
        out[setup.name] = (setup, run_campaign(setup, seed))
        if progress is not None:
            progress(setup.name)
    return out
