"""A protocol planned for one component: concrete tests with frequencies, rates and lengths.

Planning resolves mode names to the component's eigenfrequencies and rejects protocols that
cannot be run as described (:class:`motoflex_ros.errors.ProtocolError`): a ramp too fast for
the first mode, a frequency at or above the sensor's Nyquist rate, a sweep that does not end
below the first eigenfrequency. Each message starts with the protocol's file and the dotted key
to change, as a ConfigError's does.
"""
import math
from dataclasses import dataclass

import numpy as np

from motoflex_ros.bench.actuator import LATERAL_WRENCH
from motoflex_ros.bench.clamped_modes import clamped_modes
from motoflex_ros.bench.protocols import MATCH_STATIC
from motoflex_ros.bench.response import harmonic_peak_motion
from motoflex_ros.errors import ProtocolError
from motoflex_ros.identify.principal import MOMENT_TESTS, unit_wrenches
from motoflex_ros.limits import amount, check_limit

MAX_ROTATION_RAD = 0.05  # [rad] largest end rotation of a test: small, linear deformation
DECAY_ALIAS_SHARE = 0.01  # modes swinging more than 1 % of the largest in a decay...
DECAY_NYQUIST_FACTOR = 2.2  # ... are sampled at 2.2 x their frequency (10 % below Nyquist)
LOAD_MARGIN = 1.5  # a reported load may reach 1.5 x the largest commanded one

__all__ = ["TestPlan", "CampaignPlan", "plan_campaign", "sweep_frequencies", "onset_times",
           "matched_amplitude", "check_linear", "protocol_error", "decay_swing_shares",
           "check_work",
           "MAX_ROTATION_RAD", "DECAY_ALIAS_SHARE", "DECAY_NYQUIST_FACTOR", "LOAD_MARGIN"]


@dataclass(frozen=True)
class TestPlan:
    """One test. kind: 'static', 'harmonic', 'sweep' or 'decay'. rate_hz [Hz] sample rate,
    max_samples the longest it may run, amplitude_n [N] (F_st, amplitude or preload),
    frequency_hz [Hz] (harmonic), ramp_time_s [s] (static), onset_time_s [s] (load envelope) and
    read_time_s [s] (peaks read after it) of harmonic tests; ``key`` the protocol's dotted key
    of the test's load (static.force_n, harmonic.tests[i].amplitude_n...); ``wrench`` the unit
    wrench at q0 the amplitude multiplies (F_y; a unit moment for the moment tests, whose
    amplitude_n is then in N m)."""

    name: str
    kind: str
    rate_hz: float
    max_samples: int
    amplitude_n: float
    frequency_hz: float = 0.0
    ramp_time_s: float = 0.0
    onset_time_s: float = 0.0
    read_time_s: float = 0.0
    key: str = ""
    wrench: tuple = LATERAL_WRENCH


@dataclass(frozen=True)
class CampaignPlan:
    """All tests of a campaign in order, with the protocol and the component's modes."""

    tests: tuple
    protocol: object
    modes: object

    def test(self, name):
        """The test called ``name``."""
        return next(t for t in self.tests if t.name == name)

    @property
    def load_limit_n(self):
        """Largest |F_y| [N] a bench may report for this campaign: LOAD_MARGIN times the largest
        load it commands (a measured load overshoots its command a little; a load past this is
        a fault of the bench or of a message, and stops the run)."""
        return LOAD_MARGIN * max((abs(t.amplitude_n) for t in self.tests
                                  if t.wrench == LATERAL_WRENCH), default=0.0)

    @property
    def load_limit_nm(self):
        """Largest |M| [N m] a bench may report: LOAD_MARGIN times the largest moment it
        commands (0 without moment tests)."""
        return LOAD_MARGIN * max((abs(t.amplitude_n) for t in self.tests
                                  if t.wrench != LATERAL_WRENCH), default=0.0)


def protocol_error(protocol, key, problem):
    """ProtocolError '<protocol file>: key '<dotted key>': <problem>' (as a ConfigError reads)."""
    return ProtocolError(f"{protocol.source or 'protocol'}: key '{key}': {problem}")


def _check_rate(name, frequency, protocol, key):
    sensor = protocol.sensor
    if frequency >= sensor.nyquist_hz:
        raise protocol_error(protocol, key, f"test '{name}': frequency {frequency:.6g} Hz is at "
                                            f"or above the Nyquist rate {sensor.nyquist_hz:.6g}"
                                            f" Hz of the sensor (sensor.max_rate_hz "
                                            f"{sensor.max_rate_hz:.6g})")


def _static(protocol, modes):
    s = protocol.static
    f1 = modes.first_lateral().f_hz
    if s.ramp_time_s * f1 < s.min_ramp_periods:
        raise protocol_error(
            protocol, "static.ramp_time_s",
            f"ramp_time_s {s.ramp_time_s:g} s is shorter than min_ramp_periods "
            f"{s.min_ramp_periods:g} periods of the first mode ({f1:.4g} Hz), i.e. "
            f"{s.min_ramp_periods / f1:.4g} s; the ramp would excite the dynamics")
    if s.sample_rate_hz > protocol.sensor.max_rate_hz:
        raise protocol_error(protocol, "static.sample_rate_hz",
                             f"sample_rate_hz {s.sample_rate_hz:g} exceeds the sensor's "
                             f"max_rate_hz {protocol.sensor.max_rate_hz:g}")
    if round(s.hold_time_s * s.sample_rate_hz) < 10:
        raise protocol_error(protocol, "static.hold_time_s",
                             f"hold_time_s {s.hold_time_s:g} s gives fewer than 10 samples at "
                             f"{s.sample_rate_hz:g} Hz to read at the maximum")
    n = round((s.ramp_time_s + s.hold_time_s) * s.sample_rate_hz) + 1
    return TestPlan("static", "static", s.sample_rate_hz, n, s.force_n,
                    ramp_time_s=round(s.ramp_time_s * s.sample_rate_hz) / s.sample_rate_hz,
                    key="static.force_n")


def _moments(protocol, static, q0):
    """The moment tests (the static test's ramp and rate, the moments' hold; unit moments
    along O-q0 and its normal, :func:`motoflex_ros.identify.principal.unit_wrenches`)."""
    units = unit_wrenches(q0)
    m = protocol.moments
    hold = protocol.static.hold_time_s if m.hold_time_s is None else m.hold_time_s
    if round(hold * static.rate_hz) < 10:
        raise protocol_error(protocol, "moments.hold_time_s",
                             f"hold_time_s {hold:g} s gives fewer than 10 samples at "
                             f"{static.rate_hz:g} Hz to read at the maximum")
    n = round((static.ramp_time_s + hold) * static.rate_hz) + 1
    amplitudes = (m.axial_nm, m.normal_nm)
    keys = ("moments.axial_nm", "moments.normal_nm")
    return [TestPlan(name, "static", static.rate_hz, n, amp,
                     ramp_time_s=static.ramp_time_s, key=key,
                     wrench=tuple(float(v) for v in units[name]))
            for name, amp, key in zip(MOMENT_TESTS, amplitudes, keys)]


def onset_times(frequency, settings, modes):
    """Envelope duration and reading start [s] of a harmonic test, in whole periods.

    The load amplitude rises smoothly over the envelope duration: at least ``onset_periods``
    periods and ``onset_beat_cycles`` beats 1/|f_i - f| with every torsion/bending mode f_i
    not at resonance (a smooth onset much longer than the beat period hardly excites the free
    vibration of mode i, so the response starts close to its steady state). When f lies in the
    half-power band of a mode (|f - f_i| <= 2 zeta_i f_i: a resonance test) that mode's
    amplitude still has to build up, which takes a few time constants 1/(zeta_i w_i) (16
    periods at zeta = 0.01) whatever the envelope; the peaks are then read only after a further
    ``onset_time_constants`` time constants.
    """
    envelope, wait = settings.onset_periods / frequency, 0.0
    for mode in modes.modes:
        if mode.label not in ("torsion", "bending"):
            continue
        gap = abs(mode.f_hz - frequency)
        if gap <= 2.0 * mode.zeta * mode.f_hz:
            wait = max(wait, settings.onset_time_constants / (mode.zeta * mode.omega_n))
        else:
            envelope = max(envelope, settings.onset_beat_cycles / gap)
    envelope = math.ceil(envelope * frequency - 1e-9) / frequency
    return envelope, envelope + math.ceil(wait * frequency - 1e-9) / frequency


def _harmonic(name, kind, frequency, amplitude, protocol, modes, keys):
    """TestPlan of a harmonic test; keys: the protocol keys of its frequency and amplitude."""
    _check_rate(name, frequency, protocol, keys[0])
    h = protocol.harmonic
    rate = min(h.samples_per_period * frequency, protocol.sensor.max_rate_hz)
    onset, read = onset_times(frequency, h, modes)
    n = int(math.ceil((read + h.max_periods / frequency) * rate)) + 1
    return TestPlan(name, kind, rate, n, amplitude, frequency_hz=frequency, onset_time_s=onset,
                    read_time_s=read, key=keys[1])


def _sweep_end_key(sweep):
    """The protocol key that sets where the sweep ends."""
    return "sweep.end_hz" if sweep.end_hz is not None else "sweep.end_below_first_hz"


def sweep_frequencies(protocol, first_hz):
    """Sweep frequencies [Hz] of the protocol's sweep: start_hz, start_hz + step_hz, ... and
    the end frequency (end_hz, or end_below_first_hz below the first eigenfrequency [Hz])."""
    sweep = protocol.sweep
    end = sweep.end_hz if sweep.end_hz is not None else first_hz - sweep.end_below_first_hz
    key = _sweep_end_key(sweep)
    if end >= first_hz:
        raise protocol_error(protocol, key, f"the sweep ends at {end:.6g} Hz, which is not "
                                            f"below the first eigenfrequency {first_hz:.6g} Hz")
    if end < sweep.start_hz:
        raise protocol_error(protocol, key, f"the sweep ends at {end:.6g} Hz, below its "
                                            f"start_hz {sweep.start_hz:g} Hz")
    # sized before the list is made: every test samples at least one period (the whole
    # campaign is checked when planned, check_work)
    count = math.ceil((end - sweep.start_hz) / sweep.step_hz) + 1
    check_limit("samples", count * protocol.harmonic.samples_per_period,
                protocol.source or "protocol", "sweep.step_hz",
                f"a sweep of {count} tests from {sweep.start_hz:g} to {end:.6g} Hz")
    freqs = list(np.arange(sweep.start_hz, end - 1e-9 * end, sweep.step_hz))
    return tuple(float(f) for f in freqs) + (float(end),)


def decay_swing_shares(reduced, force):
    """Each mode's share of the loaded-end swing after release from a static lateral force.

    Parameters
    ----------
    reduced : ReducedComponent
        Clamped reduced model (mass-normalised ``mode_shapes``, classical modal damping).
    force : float
        Preload F_y at the loaded end [N].

    Returns
    -------
    ndarray
        Per mode (ascending frequency): its loaded-end amplitude max(|u|, L |theta|) in the
        free decay from x0 = K^-1 F, modal coordinate eta_i = phi_i^T M x0, over the largest
        mode's [-].

    """
    x0 = np.linalg.solve(reduced.K, reduced.end_load_vector([0.0, force, 0.0, 0.0, 0.0, 0.0]))
    phi = reduced.mode_shapes
    end = phi[reduced.end_dofs] * (phi.T @ (reduced.M @ x0))
    length = float(np.linalg.norm(reduced.q0))
    swing = np.maximum(np.linalg.norm(end[:3], axis=0), length * np.linalg.norm(end[3:], axis=0))
    return swing / swing.max()


def _decay(protocol, modes, reduced):
    """Free decay: samples_per_period per period of the higher target mode, and at least
    DECAY_NYQUIST_FACTOR x the highest mode swinging more than DECAY_ALIAS_SHARE of the
    largest (up to the sensor's maximum rate), so that no excited mode folds onto the targets
    (at 8 x 93 Hz the frame's 676 and 1434 Hz modes folded to 69.5 and 56 Hz and biased the
    bending zeta by -2.8 %)."""
    m = protocol.modal
    targets = [modes.first(label).f_hz for label in ("torsion", "bending")]
    f_low, f_high = min(targets), max(targets)
    _check_rate("modal", f_high, protocol, "sensor.max_rate_hz")
    shares = decay_swing_shares(reduced, m.preload_n)
    f_excited = float(np.max(reduced.frequencies_hz[shares > DECAY_ALIAS_SHARE]))
    rate = min(max(m.samples_per_period * f_high, DECAY_NYQUIST_FACTOR * f_excited),
               protocol.sensor.max_rate_hz)
    n = int(math.ceil(m.decay_periods * rate / f_low)) + 2
    return TestPlan("decay", "decay", rate, n, m.preload_n, key="modal.preload_n")


def _deformation_size(end_motion, length):
    """max(|u|, L |theta|) of a loaded-end motion [m]."""
    return max(np.linalg.norm(end_motion[:3]), length * np.linalg.norm(end_motion[3:]))


def matched_amplitude(reduced, frequency, static_force):
    """Force amplitude [N] whose steady peak deformation at frequency [Hz] equals that of the
    static force [N] (deformation measured as max(|u|, L |theta|) at the loaded end)."""
    length = float(np.linalg.norm(reduced.q0))
    load = np.zeros(reduced.K.shape[0])
    load[reduced.end_dofs[1]] = static_force
    static = np.linalg.solve(reduced.K, load)[reduced.end_dofs]
    dynamic = harmonic_peak_motion(reduced, frequency)
    return _deformation_size(static, length) / _deformation_size(dynamic, length)


def check_linear(plan, reduced, protocol):
    """ProtocolError when a test's peak end rotation exceeds MAX_ROTATION_RAD (not small)."""
    load = reduced.end_load_vector(plan.amplitude_n * np.asarray(plan.wrench, float))
    if plan.kind in ("static", "decay"):
        motion = np.linalg.solve(reduced.K, load)[reduced.end_dofs]
    else:
        motion = harmonic_peak_motion(reduced, plan.frequency_hz, plan.amplitude_n)
    rotation = float(np.linalg.norm(motion[3:]))
    if rotation > MAX_ROTATION_RAD:
        raise protocol_error(
            protocol, plan.key,
            f"test '{plan.name}': the load {plan.amplitude_n:.4g} "
            f"{'N' if plan.wrench == LATERAL_WRENCH else 'N m'} turns the loaded end by "
            f"{rotation:.3g} rad (> {MAX_ROTATION_RAD} rad); the deformation would not stay "
            f"small and linear, lower the load")


def _length_key(plan, protocol):
    """The protocol key that sets most of how long a planned test runs."""
    if plan.kind == "static":
        hold = plan.max_samples / plan.rate_hz - plan.ramp_time_s
        return "static.ramp_time_s" if plan.ramp_time_s > hold else "static.hold_time_s"
    if plan.kind == "decay":
        return "modal.decay_periods"
    # a harmonic test: the onset envelope (onset periods or beats), the wait for a resonance
    # to build up (time constants), then the periods read
    envelope = plan.onset_time_s
    if envelope * plan.frequency_hz <= protocol.harmonic.onset_periods + 1:
        envelope_key = "harmonic.onset_periods"
    else:
        envelope_key = "harmonic.onset_beat_cycles"
    parts = {envelope_key: envelope,
             "harmonic.onset_time_constants": plan.read_time_s - plan.onset_time_s,
             "harmonic.max_periods": plan.max_samples / plan.rate_hz - plan.read_time_s}
    return max(parts, key=parts.get)


def check_work(tests, protocol):
    """ConfigError (the protocol file and the key that sets the longest test) when the
    planned tests together exceed the 'samples' or 'simulated_s' limit (motoflex_ros.limits):
    checked before anything is simulated (a decay of 1e9 periods hung the identification)."""
    source = protocol.source or "protocol"
    for name, size, unit in (("samples", lambda t: t.max_samples, "samples"),
                             ("simulated_s", lambda t: t.max_samples / t.rate_hz, "s")):
        total = sum(size(t) for t in tests)
        longest = max(tests, key=size)
        check_limit(name, total, source, _length_key(longest, protocol),
                    f"the campaign of {len(tests)} tests (the longest, '{longest.name}': "
                    f"{amount(size(longest))} {unit})")


def plan_campaign(protocol, reduced, modes=None):
    """CampaignPlan of ``protocol`` for a ReducedComponent (its ModeSet computed if None).

    Each test is also checked to stay linear: :func:`check_linear`.
    """
    modes = modes if modes is not None else clamped_modes(reduced)
    tests = [_static(protocol, modes)]
    if protocol.moments is not None:
        tests += _moments(protocol, tests[0], reduced.q0)
    for i, t in enumerate(protocol.harmonic_tests):
        freq = modes.frequency(t.frequency) if isinstance(t.frequency, str) else t.frequency
        amp = t.amplitude_n
        if amp == MATCH_STATIC:
            amp = matched_amplitude(reduced, freq, protocol.static.force_n)
        key = f"harmonic.tests[{i}]"
        tests.append(_harmonic(t.name, "harmonic", freq, amp, protocol, modes,
                               (f"{key}.frequency", f"{key}.amplitude_n")))
    if protocol.sweep is not None:
        keys = (_sweep_end_key(protocol.sweep), "sweep.amplitude_n")
        for i, f in enumerate(sweep_frequencies(protocol, modes.first_lateral().f_hz)):
            tests.append(_harmonic(f"sweep_{i:02d}", "sweep", f, protocol.sweep.amplitude_n,
                                   protocol, modes, keys))
    if protocol.modal is not None:
        tests.append(_decay(protocol, modes, reduced))
    check_work(tests, protocol)
    for plan in tests:
        check_linear(plan, reduced, protocol)
    return CampaignPlan(tuple(tests), protocol, modes)
