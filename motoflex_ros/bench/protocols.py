"""Bench protocols in YAML (config/protocols/*.yaml), validated on load.

A protocol file describes one bench campaign (Passigato et al. 2023, Sect. 4.2): the sensor,
the quasi-static test (slow ramp to F_st, hold, read at the maximum), harmonic tests at fixed
frequencies (a number [Hz] or ``first torsion`` / ``first bending`` / ``first``, resolved from
the component's modes), the frequency sweep (harmonic tests from ``start_hz`` to 5 Hz below the
first eigenfrequency) and the modal test (release from a static preload, free decay). Every
force is an amplitude at the loaded end [N]; choose it so that the deformation stays small
(linear), as the paper does. Checks that need the component (ramp slow enough, frequencies
below the sensor's Nyquist rate, sweep ending below the first eigenfrequency) are made when the
protocol is planned for a component (:mod:`motoflex_ros.bench.plan`).
"""
from dataclasses import dataclass

from motoflex_ros.bench.sensor import DEFAULT_MARKERS, SensorSettings
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

__all__ = ["StaticTest", "HarmonicSettings", "HarmonicTest", "SweepTest", "ModalTest",
           "Protocol", "load_protocol", "protocol_for", "PROTOCOL_SCHEMA", "MODE_FREQUENCIES",
           "MATCH_STATIC"]

MODE_FREQUENCIES = ("first", "first torsion", "first bending")
MATCH_STATIC = "match_static"

_SENSOR = Field("mapping", required=False, default=None, fields={
    "noise_m": number(0.0, required=False, default=5e-6, help="noise std [m] >= 0"),
    "resolution_m": number(0.0, required=False, default=1e-7, help="resolution [m] >= 0"),
    "max_rate_hz": positive(required=False, default=5000.0, help="maximum frame rate [Hz]"),
    "latency_s": number(0.0, 1.0, required=False, default=0.001, help="latency [s]"),
    "markers": Field("list", required=False, default=None, min_items=3,
                     item=Field("vec3"), help="marker offsets from q0 [m], >= 3"),
})
_STATIC = Field("mapping", fields={
    "force_n": positive(help="F_st [N] > 0"),
    "ramp_time_s": positive(help="ramp time [s] > 0"),
    "hold_time_s": positive(help="hold time [s] > 0"),
    "sample_rate_hz": positive(help="sample rate [Hz] > 0"),
    "min_ramp_periods": number(1.0, required=False, default=5.0,
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
    "onset_beat_cycles": number(0.0, required=False, default=4.0,
                                help="onset at least this many beats with the nearest mode"),
    "onset_time_constants": number(0.0, required=False, default=4.0,
                                   help="at resonance, onset at least this many 1/(zeta w)"),
    "band_length_m": positive(help="tolerance band of the running mean of l, b [m] > 0"),
    "band_angle_rad": positive(help="tolerance band of the running mean of beta [rad] > 0"),
    "settle_peaks": Field("int", 2, 10000, help="peaks the mean must stay in the band"),
    "max_periods": number(1.0, help="maximum periods read after the onset, >= 1"),
    "tests": Field("list", item=_HARMONIC_TEST, required=False, default=[]),
})
_SWEEP = Field("mapping", required=False, default=None, fields={
    "amplitude_n": positive(help="force amplitude [N] > 0"),
    "start_hz": positive(help="first frequency [Hz] > 0"),
    "step_hz": positive(help="frequency step [Hz] > 0"),
    "end_below_first_hz": positive(required=False, default=None,
                                   help="end this far below the first eigenfrequency [Hz]"),
    "end_hz": positive(required=False, default=None, help="last frequency [Hz]"),
})
_MODAL = Field("mapping", required=False, default=None, fields={
    "preload_n": positive(help="static preload released at t = 0 [N] > 0"),
    "decay_periods": positive(help="record length in periods of the lowest target mode"),
    "samples_per_period": Field("int", 4, 1000, help="samples per period of the highest "
                                                     "target mode, 4..1000"),
})
PROTOCOL_SCHEMA = Field("mapping", fields={
    "description": Field("str", required=False, default=""),
    "sensor": _SENSOR, "static": _STATIC, "harmonic": _HARMONIC, "sweep": _SWEEP,
    "modal": _MODAL,
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


def _check_amplitude(value, source, key):
    """A harmonic amplitude: a number > 0 [N] or 'match_static'."""
    if value == MATCH_STATIC:
        return value
    if isinstance(value, str):
        raise ConfigError(source, key, f"'{value}' is not an amplitude; allowed: a number > 0 "
                                       f"[N] or '{MATCH_STATIC}'")
    return validate(value, positive(), source, key)


def _check_frequency(value, source, key):
    """A harmonic test frequency: a number > 0 [Hz] or a mode name."""
    if isinstance(value, str):
        if value not in MODE_FREQUENCIES:
            raise ConfigError(source, key, f"'{value}' is not a frequency; allowed: a number "
                                           f"> 0 [Hz] or one of: {', '.join(MODE_FREQUENCIES)}")
        return value
    return validate(value, positive(), source, key)


def _sensor(data):
    if data is None:
        return SensorSettings()
    markers = tuple(tuple(m) for m in data["markers"]) if data["markers"] else DEFAULT_MARKERS
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


def load_protocol(name_or_file):
    """Load and validate a protocol (shipped name or YAML path) into a :class:`Protocol`."""
    path = resolve_config("protocols", name_or_file)
    data = load_config(path, PROTOCOL_SCHEMA)
    h = dict(data["harmonic"])
    tests = []
    for i, t in enumerate(h.pop("tests")):
        freq = _check_frequency(t["frequency"], path, f"harmonic.tests[{i}].frequency")
        amp = _check_amplitude(t["amplitude_n"], path, f"harmonic.tests[{i}].amplitude_n")
        tests.append(HarmonicTest(t["name"], freq, amp))
    names = [t.name for t in tests]
    if len(set(names)) != len(names):
        raise ConfigError(path, "harmonic.tests", f"test names must be unique, got {names}")
    return Protocol(sensor=_sensor(data["sensor"]), static=StaticTest(**data["static"]),
                    harmonic=HarmonicSettings(**h), harmonic_tests=tuple(tests),
                    sweep=_sweep(data["sweep"], path),
                    modal=ModalTest(**data["modal"]) if data["modal"] else None,
                    description=data["description"], source=str(path))


def protocol_for(component_name):
    """The shipped protocol of a component (``<name>.yaml``), else ``default``."""
    shipped = shipped_configs("protocols")
    return load_protocol(component_name if component_name in shipped else "default")
