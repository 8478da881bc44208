"""Bench protocols in YAML (config/protocols/*.yaml), validated on load.

A protocol file describes one bench campaign (Passigato et al. 2023, Sect. 4.2): the sensor,
the quasi-static test (slow ramp to F_st, hold, read at the maximum), harmonic tests at fixed
frequencies (a number [Hz] or ``first torsion`` / ``first bending`` / ``first``, resolved from
the component's modes; two of them named ``torsion`` and ``bending`` for the identification's
models, others are extra tests), the frequency sweep (harmonic tests from ``start_hz`` to 5 Hz
below the first eigenfrequency) and the modal test (release from a static preload, free
decay), and, beyond the paper, ``road_load``: the quasi-static test with the force applied
through a rigid lever (point and direction settable; default the tyre contact point of the
vehicle's static configuration and a lateral force), and ``moments``: two more quasi-static
tests (the static test's ramp and hold) with a moment at the loaded end about the component's
own axes, along O-q0 (``axial_nm``) and along its normal in the x-z plane (``normal_nm``), for
the principal hinges (:mod:`motoflex_ros.identify.principal`; on a physical bench a moment is
a force pair or a lever). Every force is an amplitude at the
loaded end [N] (the road_load's at its lever point); choose it so that the deformation stays
small (linear), as the paper does. Checks that need the component (ramp slow enough,
frequencies below the sensor's Nyquist rate, sweep ending below the first eigenfrequency) are
made when the protocol is planned for a component (:mod:`motoflex_ros.bench.plan`).
"""
from dataclasses import dataclass

import numpy as np

from motoflex_ros.bench.sensor import DEFAULT_MARKERS, MAX_NOISE_M, SensorSettings
from motoflex_ros.config import (
    Field,
    load_config,
    number,
    positive,
    resolve_config,
    shipped_configs,
    validate,
)
from motoflex_ros.errors import ConfigError
from motoflex_ros.identify.principal import MOMENT_TESTS
from motoflex_ros.identify.results import MEASURED_KEY, MODEL_TESTS, RESULT_KEYS

__all__ = ["StaticTest", "RoadLoadTest", "MomentTests", "MOMENT_NM", "HarmonicSettings",
           "HarmonicTest", "SweepTest", "ModalTest", "Protocol", "load_protocol", "protocol_for",
           "PROTOCOL_SCHEMA",
           "MODE_FREQUENCIES", "MATCH_STATIC", "REQUIRED_HARMONIC_TESTS", "RESERVED_TEST_NAMES",
           "MIN_MARKER_SPREAD_M"]

MODE_FREQUENCIES = ("first", "first torsion", "first bending")
MATCH_STATIC = "match_static"
REQUIRED_HARMONIC_TESTS = tuple(t for t in MODEL_TESTS if t != "static")
"""Harmonic tests every protocol has: the identification's torsion and bending models."""
RESERVED_TEST_NAMES = ("static", "decay") + MOMENT_TESTS + RESULT_KEYS + (MEASURED_KEY,)
"""Names a harmonic test may not have: the plan's own tests (static, decay, the moment tests;
the sweep's are
sweep_00, sweep_01...) and the keys of the results; nor may a name start with 'sweep'."""
MIN_MARKER_SPREAD_M = 1e-3
"""Smallest second singular value [m] of the centred marker offsets (their spread across the
line that fits them best). Below it the markers lie (nearly) on a line and the rotation about
that line is not observed: collinear or coincident markers have a spread at round-off level
(~1e-17 m). The fit's rotation about the line scatters by about noise_m / spread per frame:
5 mrad at the shipped 5 um noise and a 1 mm spread, more than the smallest end rotation of a
shipped test (0.8 mrad, the swingarm's static test), so a smaller spread can only give noise.
It is a lower bound, not a guarantee: with 5 um noise the swingarm's torsion k is 19 % off at a
12 mm spread and 6 % off at 36 mm (the shipped markers: 184 mm)."""

# Physical ranges of the protocol's numbers (SI). The length of each test is also bounded by
# the work limits of motoflex_ros.limits when the protocol is planned (bench/plan.py).
FORCE_N = (1e-3, 1e6)  # [N]; a smaller load's deformation underflows (preload 1e-300 N)
MAX_FREQUENCY_HZ = 1e6
MAX_TIME_S = 3600.0
MAX_PERIODS = 1e5
MAX_SIZE_M = 10.0
MOMENT_NM = (1e-3, 1e6)  # [N m]

_SENSOR = Field("mapping", required=False, default=None, fields={
    "noise_m": number(0.0, MAX_NOISE_M, required=False, default=5e-6,
                      help=f"noise std [m] in [0, {MAX_NOISE_M:g}]"),
    "resolution_m": number(0.0, MAX_NOISE_M, required=False, default=1e-7,
                           help="resolution [m]"),
    "max_rate_hz": positive(MAX_FREQUENCY_HZ, required=False, default=5000.0,
                            help="maximum frame rate [Hz]"),
    "latency_s": number(0.0, 1.0, required=False, default=0.001, help="latency [s]"),
    "markers": Field("list", required=False, default=None, min_items=3,
                     item=Field("vec3", -MAX_SIZE_M, MAX_SIZE_M),
                     help="marker offsets from q0 [m], >= 3"),
})
_STATIC = Field("mapping", fields={
    "force_n": number(*FORCE_N, help="F_st [N]"),
    "ramp_time_s": positive(MAX_TIME_S, help="ramp time [s]"),
    "hold_time_s": positive(MAX_TIME_S, help="hold time [s]"),
    "sample_rate_hz": positive(MAX_FREQUENCY_HZ, help="sample rate [Hz]"),
    "min_ramp_periods": number(1.0, MAX_PERIODS, required=False, default=5.0,
                               help="ramp time in periods of the first mode, >= 1"),
})
_HARMONIC_TEST = Field("mapping", fields={
    "name": Field("str"),
    "frequency": Field("any", help="[Hz] > 0, or one of: " + ", ".join(MODE_FREQUENCIES)),
    "amplitude_n": Field("any", help="force amplitude [N] > 0, or 'match_static'"),
})
_HARMONIC = Field("mapping", fields={
    "samples_per_period": Field("int", 4, 1000, help="samples per period, 4..1000"),
    "onset_periods": Field("int", 0, 1000, required=False, default=3,
                           help="smooth onset, at least this many periods"),
    "onset_beat_cycles": number(0.0, 1000.0, required=False, default=4.0,
                                help="onset at least this many beats with the nearest mode"),
    "onset_time_constants": number(0.0, 1000.0, required=False, default=4.0,
                                   help="at resonance, onset at least this many 1/(zeta w)"),
    "band_length_m": positive(MAX_SIZE_M, help="tolerance band of the running mean of l, b "
                                               "[m]"),
    "band_angle_rad": positive(3.15, help="tolerance band of the running mean of beta [rad]"),
    "settle_peaks": Field("int", 2, 10000, help="peaks the mean must stay in the band"),
    "max_periods": number(1.0, MAX_PERIODS, help="maximum periods read after the onset"),
    "tests": Field("list", item=_HARMONIC_TEST,
                   help="harmonic tests; torsion and bending required"),
})
_SWEEP = Field("mapping", required=False, default=None, fields={
    "amplitude_n": number(*FORCE_N, help="force amplitude [N]"),
    "start_hz": positive(MAX_FREQUENCY_HZ, help="first frequency [Hz]"),
    "step_hz": positive(MAX_FREQUENCY_HZ, help="frequency step [Hz]"),
    "end_below_first_hz": positive(MAX_FREQUENCY_HZ, required=False, default=None,
                                   help="end this far below the first eigenfrequency [Hz]"),
    "end_hz": positive(MAX_FREQUENCY_HZ, required=False, default=None,
                       help="last frequency [Hz]"),
})
_MODAL = Field("mapping", required=False, default=None, fields={
    "preload_n": number(*FORCE_N, help="static preload released at t = 0 [N]"),
    "decay_periods": positive(MAX_PERIODS, help="record length in periods of the lowest "
                                                "target mode"),
    "samples_per_period": Field("int", 4, 1000, help="samples per period of the highest "
                                                     "target mode, 4..1000"),
})
_ROAD_LOAD = Field("mapping", required=False, default=None, fields={
    "point_m": Field("vec3", -MAX_SIZE_M, MAX_SIZE_M, required=False, default=None,
                     help="lever point, component frame [m] (default: the tyre contact point "
                          "of the vehicle's static configuration)"),
    "direction": Field("vec3", -1e3, 1e3, required=False, default=[0.0, 1.0, 0.0],
                       help="force direction (normalised; default lateral, [0, 1, 0])"),
    "force_n": number(*FORCE_N, required=False, default=None,
                      help="force [N] (default: static.force_n)"),
})
_MOMENTS = Field("mapping", required=False, default=None, fields={
    "axial_nm": number(*MOMENT_NM, help="moment along O-q0 [N m]"),
    "normal_nm": number(*MOMENT_NM, help="moment along the normal of O-q0 in the x-z plane "
                                         "[N m]"),
    "hold_time_s": positive(MAX_TIME_S, required=False, default=None,
                            help="hold [s] (default: static.hold_time_s)"),
})
PROTOCOL_SCHEMA = Field("mapping", fields={
    "description": Field("str", required=False, default=""),
    "sensor": _SENSOR, "static": _STATIC, "harmonic": _HARMONIC, "sweep": _SWEEP,
    "modal": _MODAL, "road_load": _ROAD_LOAD, "moments": _MOMENTS,
})


@dataclass(frozen=True)
class StaticTest:
    """Quasi-static test: cosine ramp to force_n [N] over ramp_time_s [s], hold_time_s [s]."""

    force_n: float
    ramp_time_s: float
    hold_time_s: float
    sample_rate_hz: float
    min_ramp_periods: float


@dataclass(frozen=True)
class HarmonicSettings:
    """Sampling, onset and stop criterion shared by the harmonic and sweep tests."""

    samples_per_period: int
    onset_periods: int
    onset_beat_cycles: float
    onset_time_constants: float
    band_length_m: float
    band_angle_rad: float
    settle_peaks: int
    max_periods: float


@dataclass(frozen=True)
class HarmonicTest:
    """One harmonic test: frequency [Hz] or a mode name; force amplitude [N] or
    'match_static' (the amplitude whose steady peak deformation equals the static test's)."""

    name: str
    frequency: object
    amplitude_n: float


@dataclass(frozen=True)
class SweepTest:
    """Harmonic tests from start_hz in steps of step_hz [Hz] up to end_hz or to
    end_below_first_hz below the first eigenfrequency."""

    amplitude_n: float
    start_hz: float
    step_hz: float
    end_below_first_hz: float = None
    end_hz: float = None


@dataclass(frozen=True)
class ModalTest:
    """Free decay after releasing a static preload [N]."""

    preload_n: float
    decay_periods: float
    samples_per_period: int


@dataclass(frozen=True)
class RoadLoadTest:
    """Quasi-static test loaded through a rigid lever (beyond the paper): the force force_n
    [N] (None: the static test's) along ``direction`` (unit) at ``point_m`` [m] (component
    frame; None: the tyre contact point of the vehicle's static configuration), the ramp and
    hold of the static test."""

    point_m: tuple = None
    direction: tuple = (0.0, 1.0, 0.0)
    force_n: float = None


@dataclass(frozen=True)
class MomentTests:
    """The moment tests of the principal hinges (beyond the paper): moments [N m] at q0 along
    O-q0 (axial_nm) and along its normal in the x-z plane (normal_nm), with the static test's
    ramp and rate and a hold of hold_time_s [s] (None: the static test's)."""

    axial_nm: float
    normal_nm: float
    hold_time_s: float = None


@dataclass(frozen=True)
class Protocol:
    """A validated bench campaign; ``source`` is the file it came from."""

    sensor: SensorSettings
    static: StaticTest
    harmonic: HarmonicSettings
    harmonic_tests: tuple
    sweep: SweepTest = None
    modal: ModalTest = None
    description: str = ""
    source: str = ""
    road_load: RoadLoadTest = RoadLoadTest()
    moments: MomentTests = None


def _check_amplitude(value, source, key):
    """A harmonic amplitude: a number > 0 [N] or 'match_static'."""
    if value == MATCH_STATIC:
        return value
    if isinstance(value, str):
        raise ConfigError(source, key, f"'{value}' is not an amplitude; allowed: a number > 0 "
                                       f"[N] or '{MATCH_STATIC}'")
    return validate(value, number(*FORCE_N), source, key)


def _check_frequency(value, source, key):
    """A harmonic test frequency: a number > 0 [Hz] or a mode name."""
    if isinstance(value, str):
        if value not in MODE_FREQUENCIES:
            raise ConfigError(source, key, f"'{value}' is not a frequency; allowed: a number "
                                           f"> 0 [Hz] or one of: {', '.join(MODE_FREQUENCIES)}")
        return value
    return validate(value, positive(MAX_FREQUENCY_HZ), source, key)


def _check_markers(markers, source, key):
    """Marker offsets [m] whose centred positions span a plane (second singular value at least
    :data:`MIN_MARKER_SPREAD_M`), so that the rigid fit observes every rotation."""
    offsets = np.asarray(markers, float)
    spread = np.linalg.svd(offsets - offsets.mean(axis=0), compute_uv=False)[1]
    if spread < MIN_MARKER_SPREAD_M:
        raise ConfigError(source, key, f"the markers are collinear or coincident (second "
                                       f"singular value of the centred offsets {spread:.3g} m, "
                                       f"allowed >= {MIN_MARKER_SPREAD_M:g} m); the rotation "
                                       f"about their line cannot be measured: place at least "
                                       f"three markers that span a plane")
    return tuple(tuple(m) for m in markers)


def _sensor(data, source):
    if data is None:
        return SensorSettings()
    markers = DEFAULT_MARKERS
    if data["markers"]:
        markers = _check_markers(data["markers"], source, "sensor.markers")
    return SensorSettings(noise_m=data["noise_m"], resolution_m=data["resolution_m"],
                          max_rate_hz=data["max_rate_hz"], latency_s=data["latency_s"],
                          markers=markers)


def _sweep(data, source):
    if data is None:
        return None
    if (data["end_hz"] is None) == (data["end_below_first_hz"] is None):
        raise ConfigError(source, "sweep", "give exactly one of end_hz [Hz] and "
                                           "end_below_first_hz [Hz]")
    return SweepTest(**data)


def _check_test_name(name, source, key):
    """A harmonic test name that is not one of :data:`RESERVED_TEST_NAMES` nor sweep*."""
    if name in RESERVED_TEST_NAMES or name.startswith("sweep"):
        raise ConfigError(source, key, f"'{name}' is reserved (not allowed: "
                                       f"{', '.join(RESERVED_TEST_NAMES)} or a name starting "
                                       f"with 'sweep'); the identification needs "
                                       f"{' and '.join(REQUIRED_HARMONIC_TESTS)}, other names "
                                       f"are extra tests")
    return name


def _harmonic_tests(specs, source):
    """HarmonicTests of harmonic.tests: unique names, torsion and bending among them."""
    tests = []
    for i, t in enumerate(specs):
        key = f"harmonic.tests[{i}]"
        name = _check_test_name(t["name"], source, f"{key}.name")
        freq = _check_frequency(t["frequency"], source, f"{key}.frequency")
        amp = _check_amplitude(t["amplitude_n"], source, f"{key}.amplitude_n")
        tests.append(HarmonicTest(name, freq, amp))
    names = [t.name for t in tests]
    if len(set(names)) != len(names):
        raise ConfigError(source, "harmonic.tests", f"test names must be unique, got {names}")
    missing = [n for n in REQUIRED_HARMONIC_TESTS if n not in names]
    if missing:
        raise ConfigError(source, "harmonic.tests", f"no test named {' or '.join(missing)} "
                                                    f"(got {names or 'none'}); the "
                                                    f"identification (eqs. 8-12) needs "
                                                    f"harmonic tests named "
                                                    f"{' and '.join(REQUIRED_HARMONIC_TESTS)}")
    return tuple(tests)


def _road_load(data, source):
    if not data:
        return RoadLoadTest()
    direction = np.asarray(data["direction"], float)
    norm = float(np.linalg.norm(direction))
    if not norm > 1e-9:
        raise ConfigError(source, "road_load.direction", "must not be the zero vector")
    point = data["point_m"]
    return RoadLoadTest(None if point is None else tuple(float(v) for v in point),
                        tuple(float(v) for v in direction / norm), data["force_n"])


def load_protocol(name_or_file):
    """Load and validate a protocol (shipped name or YAML path) into a :class:`Protocol`."""
    path = resolve_config("protocols", name_or_file)
    data = load_config(path, PROTOCOL_SCHEMA)
    h = dict(data["harmonic"])
    tests = _harmonic_tests(h.pop("tests"), path)
    return Protocol(sensor=_sensor(data["sensor"], path), static=StaticTest(**data["static"]),
                    harmonic=HarmonicSettings(**h), harmonic_tests=tests,
                    sweep=_sweep(data["sweep"], path),
                    modal=ModalTest(**data["modal"]) if data["modal"] else None,
                    description=data["description"], source=str(path),
                    road_load=_road_load(data["road_load"], path),
                    moments=MomentTests(**data["moments"]) if data["moments"] else None)


def protocol_for(component_name):
    """The shipped protocol of a component (``<name>.yaml``), else ``default``."""
    shipped = shipped_configs("protocols")
    return load_protocol(component_name if component_name in shipped else "default")
