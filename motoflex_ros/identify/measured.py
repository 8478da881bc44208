"""Identification of a physical bench from its measurements alone: no finite-element model.

Input: :class:`motoflex_ros.identify.measurements.Measurements` (one row per marker frame with
the load at its capture time; from a CSV file, a rosbag2 recording or live topics) and the
:class:`motoflex_ros.identify.bench_file.BenchFile` (q0, marker offsets, sensor). The method is
the virtual identification's (Passigato et al. 2023, Sect. 4.2; the same functions of
:mod:`motoflex_ros.identify`), with what the component's model gave there taken from the data:

- the tests and their phases: from the load history (:mod:`.segmentation`), or the labels;
- the poses of the loaded end: the rigid fit of each frame's markers to their reference (the
  bench file's offsets from q0, or their mean over the frames before the first load);
- static: l, beta, b (eqs. 1-7) of the mean pose at the held load, k by eq. (8), c = gamma k;
- harmonic tests: per window of whole periods of the fitted load frequency, the sine fit of the
  pose and its two peaks (as the virtual identifier reads them), from the first window of a
  steady response: the load at full amplitude, at a resonance of a free-decay pole a further
  4 / (zeta omega_n) (as the virtual protocols wait), and from the first window after which
  neither beta nor b of the windows trends by more than one standard error of the slope (a
  dying transient of another mode drifts the axis); which one is the torsion and which the
  bending test: the
  deformation axis (within 45 deg of O-q0: torsion, as the model's modes are labelled), the
  test nearest a free-decay pole first;
- omega_n, zeta (eq. 9) of the torsion and bending modes: from the measured free decay (matrix
  pencil, the pole within 5 % of the test's frequency) or, where the decay does not show the
  mode, from the harmonic response: a single-mode estimate from the receptance Y/F against the
  static compliance (G0 / G = 1 - r^2 + 2 j zeta r, r = omega / omega_n) when the response lags
  the load by 60-120 deg (a resonance), else omega_n = 2 pi f of the test (the test is run at the
  mode's frequency) and zeta undefined;
- J, c by eqs. (10)-(11) with the intervals of omega_n and zeta propagated, k_t, k_b by eq. (12);
- the principal hinges (:mod:`motoflex_ros.identify.principal`, beyond the paper): the moment
  tests are static tests of the torque |M| (CSV mx, my, mz; WrenchStamped torque), labelled
  moment_axial / moment_normal or found from the load; C from their holds and the static
  test's with the loads as measured, in the metric of the bench file's ``carried`` inertia.

Every value has the virtual identification's 95 % interval (from the scatter of the data);
the static one includes the scatter of a reference taken from the data. The result has the
shape of ``motoflex identify``'s, with a ``measured`` entry: the tests found, counts of frames
(dropped, unmatched), the load's noise and threshold and the rigid fit's residual.
"""
import math
from dataclasses import dataclass

import numpy as np

from motoflex_ros.identify.bench_file import MIN_REFERENCE_FRAMES, check_marker_spread
from motoflex_ros.identify.decay import decay_poles, match_pole
from motoflex_ros.identify.identifier import (
    MIN_FIT_SAMPLES,
    DecayReading,
    HarmonicReading,
    StaticReading,
)
from motoflex_ros.identify.measurements import MeasurementError, marker_columns
from motoflex_ros.identify.peaks import (
    RunningMean,
    axis_of_pose,
    fit_sine,
    peak_poses,
    unwrap_axis,
)
from motoflex_ros.identify.principal import MOMENT_TESTS, identify_principal, moment_axes
from motoflex_ros.identify.results import (
    LEVEL,
    MEASURED_KEY,
    AxisModel,
    ComponentIdentification,
    check_positive_k,
    harmonic_axis,
    mode_model,
    split_model,
    static_model,
)
from motoflex_ros.identify.segmentation import find_tests
from motoflex_ros.identify.uncertainty import interval, mean_and_covariance, propagate

__all__ = ["MeasuredIdentification", "identify_measured", "fit_poses", "label_axis",
           "TREND_T", "DECAY_SWING_FACTOR", "RESONANCE_LAG_DEG", "RIGID_FACTOR"]

TREND_T = 1.0              # steady response: no trend of beta, b beyond 1 standard error...
MIN_TREND_WINDOWS = 4      # ... over at least 4 windows (and the last quarter)
ONSET_TIME_CONSTANTS = 4.0  # at a resonance, wait 4 / (zeta omega_n) (the virtual protocols')
DECAY_SWING_FACTOR = 20.0  # a free decay swings more than 20 x the marker noise
MIN_DECAY_FRAMES = 30
MAX_DECAY_FRAMES = 20000   # a decay record is cut here (its end is noise)
RESONANCE_LAG_DEG = (60.0, 120.0)  # a harmonic test at a resonance: the response lags so
RESONANCE_DETUNING = 0.1   # ... and its single-mode omega_n is within 10 % of the test's
MAX_ZETA = 0.5             # ... with a damping ratio in (0, 0.5)
RIGID_FACTOR = 10.0        # rigid-fit residual allowed: 10 x noise_m (at least RIGID_FLOOR_M)
RIGID_FLOOR_M = 1e-5
# the virtual protocols' settling bands (config/protocols/default.yaml: harmonic.*)
BAND_LENGTH_M, BAND_ANGLE_RAD, SETTLE_PEAKS = 1e-3, 2e-3, 10
MODEL_LABELS = ("torsion", "bending")


@dataclass(frozen=True)
class MeasuredIdentification(ComponentIdentification):
    """Results of a measured bench: a ComponentIdentification whose torsion and bending models
    are None when the record has no such test, with what was measured (``measured``)."""

    measured: dict

    def to_dict(self):
        """The shape of ``motoflex identify``'s results, with the ``measured`` entry."""
        return {**super().to_dict(), MEASURED_KEY: self.measured}


def _det(m):
    return (m[:, 0, 0] * (m[:, 1, 1] * m[:, 2, 2] - m[:, 1, 2] * m[:, 2, 1])
            - m[:, 0, 1] * (m[:, 1, 0] * m[:, 2, 2] - m[:, 1, 2] * m[:, 2, 0])
            + m[:, 0, 2] * (m[:, 1, 0] * m[:, 2, 1] - m[:, 1, 1] * m[:, 2, 0]))


def fit_poses(measured, reference, q0):
    """Rigid fit (Kabsch) of each frame's markers to the reference, as
    :func:`motoflex_ros.bench.sensor.fit_pose` does one: measured (n, N, 3), reference (N, 3)
    [m], q0 (3,) [m]. Returns pose vectors (n, 6) (q - q0 [m], rotation vector [rad]) and the
    RMS residual of each frame's fit (n,) [m]."""
    measured = np.asarray(measured, float)
    reference = np.asarray(reference, float)
    scale = 1.0 / measured.shape[1]
    c_meas = measured.sum(axis=1) * scale
    c_ref = reference.sum(axis=0) * scale
    ref = reference - c_ref
    h = np.einsum("mi,nmj->nij", ref, measured - c_meas[:, None, :])
    u, _, vt = np.linalg.svd(h)
    flip = _det(u) * _det(vt) < 0.0
    vt[flip, 2, :] *= -1.0
    rotation = np.transpose(vt, (0, 2, 1)) @ np.transpose(u, (0, 2, 1))
    position = c_meas - rotation @ (c_ref - q0)
    fitted = np.einsum("nij,mj->nmi", rotation, ref) + c_meas[:, None, :]
    residual = np.sqrt(np.mean(np.sum((measured - fitted) ** 2, axis=2), axis=1))
    v = 0.5 * np.stack([rotation[:, 2, 1] - rotation[:, 1, 2],
                        rotation[:, 0, 2] - rotation[:, 2, 0],
                        rotation[:, 1, 0] - rotation[:, 0, 1]], axis=1)
    sin_angle = np.linalg.norm(v, axis=1)
    cos_angle = 0.5 * (np.trace(rotation, axis1=1, axis2=2) - 1.0)
    angle = np.arctan2(sin_angle, cos_angle)
    factor = np.where(sin_angle > 1e-300, angle / np.where(sin_angle > 1e-300, sin_angle, 1.0),
                      0.0)
    poses = np.column_stack([position - q0, v * factor[:, None]])
    return poses, residual


def label_axis(beta):
    """'torsion' for an axis within 45 deg of the line O-q0 (beta near 0 or pi), else
    'bending' (as the component model's modes are labelled)."""
    return "torsion" if (beta < np.pi / 4 or beta > 3 * np.pi / 4) else "bending"


# --- reference and poses --------------------------------------------------------------------

def _reference(data, bench, first_load):
    """Reference marker positions (N, 3) [m], the frames it came from (None: the bench file)
    and a description."""
    n = data.n_markers
    if bench.offsets is not None:
        if len(bench.offsets) != n:
            raise MeasurementError(bench.source, f"{len(bench.offsets)} marker offsets, but "
                                                 f"{data.source} has {n} markers (give one "
                                                 f"offset per marker, in the data's order)",
                                   column=None) from None
        return bench.q0 + bench.offsets, None, "bench file markers"
    if first_load < MIN_REFERENCE_FRAMES:
        raise MeasurementError(data.source, f"markers: from_data (bench file {bench.source}) "
                                            f"needs at least {MIN_REFERENCE_FRAMES} frames "
                                            f"before the first load, the load starts at frame "
                                            f"{first_load + 1} ({data.where(first_load)}, t = "
                                            f"{data.t[first_load]:.6g} s): record a quiet "
                                            f"lead-in or give the marker offsets")
    reference = data.markers[:first_load].mean(axis=0)
    columns = marker_columns(n)
    check_marker_spread(reference, data.source, f"{columns[0]}..{columns[-1]}",
                        "the markers (their mean before the first load)")
    return reference, slice(0, first_load), (f"from_data: mean of the {first_load} frames "
                                             f"before the first load (t < "
                                             f"{data.t[first_load]:.6g} s)")


def _check_rigid(data, bench, residual, reference_text):
    """MeasurementError when the markers do not move as one rigid body with the reference."""
    allowed = max(RIGID_FACTOR * bench.noise_m, RIGID_FLOOR_M)
    median = float(np.median(residual))
    if not median <= allowed:
        worst = int(np.argmax(residual))
        raise MeasurementError(
            data.source, f"the markers do not move as one rigid body with the reference "
                         f"({reference_text}): median rigid-fit residual {median:.3g} m, "
                         f"allowed <= {allowed:.3g} m (10 x sensor.noise_m of {bench.source}); "
                         f"worst at {data.where(worst)}: check the marker order, the offsets "
                         f"and that the coordinates are in the clamp frame")
    # collinear markers in the data itself: the fit then has no unique rotation
    spread = np.linalg.svd(data.markers[0] - data.markers[0].mean(axis=0), compute_uv=False)[1]
    columns = marker_columns(data.n_markers)
    check_marker_spread(data.markers[0], data.source, f"{columns[0]}..{columns[-1]}",
                        f"the markers ({data.where(0)}, spread {spread:.3g} m)")


# --- readings --------------------------------------------------------------------------------

def _static_reading(data, poses, seg, reference_frames, load=None):
    """StaticReading of a hold: the mean of ``load`` (default F_y) [N or N m], the mean pose."""
    sel = slice(seg.read_start, seg.read_stop)
    mean, cov = mean_and_covariance(poses[sel])
    if reference_frames is not None:   # the reference's own scatter shifts every pose
        cov = cov + mean_and_covariance(poses[reference_frames])[1]
    load = data.force if load is None else load
    return StaticReading(float(np.mean(load[sel])), mean, cov, seg.read_stop - seg.read_start)


def _moment_tests(data, poses, q0, reference_frames):
    """The moment tests of the principal hinges, found as static tests of the torque |M|
    (labelled moment_axial / moment_normal, or not: then named after the nearer of the axes
    along O-q0 and its normal, or the other name when that one is taken: any two independent
    moment directions serve). Returns ({name: StaticReading (amplitude |M| [N m])},
    {name: unit wrench (6,), the hold's mean wrench over |M|}, report entries)."""
    torque = np.linalg.norm(data.wrench[:, 3:], axis=1)
    if not np.any(torque):
        return {}, {}, []
    try:
        segments = find_tests(data.t, torque, data.labels, data.source, column="mx, my, mz")[0]
    except MeasurementError:
        return {}, {}, []
    e0, normal = moment_axes(q0)
    readings, units, report = {}, {}, []
    for seg in segments:
        if seg.kind != "static" or (seg.labelled and seg.name not in MOMENT_TESTS):
            continue
        wrench = data.wrench[seg.read_start:seg.read_stop].mean(axis=0)
        amplitude = float(np.linalg.norm(wrench[3:]))
        name = seg.name if seg.labelled else (
            "moment_axial" if abs(wrench[3:] @ e0) >= abs(wrench[3:] @ normal)
            else "moment_normal")
        if not seg.labelled and name in readings:
            # the names are slots, the directions are in the units: a second moment nearer the
            # same axis takes the free slot (identify_principal checks that the three loads are
            # independent and says so when they are not)
            free = [n for n in MOMENT_TESTS if n not in readings]
            name = free[0] if free else name
        entry = seg.summary(data.t) | {"name": name, "kind": "moment",
                                       "amplitude_n": amplitude}
        if name in readings:
            report.append(entry | {"used": False, "note": "another moment test about that "
                                                          "axis (the first one is used)"})
            continue
        readings[name] = _static_reading(data, poses, seg, reference_frames, torque)
        units[name] = wrench / readings[name].force
        report.append(entry | {"used": True, "model": name})
    return readings, units, report


def _windows(data, seg):
    """Window index of each frame of a harmonic segment from its steady part on, the number
    of periods per window and the frames a full window holds."""
    t = data.t[seg.read_start:seg.read_stop]
    f = seg.frequency_hz
    dt = float(np.median(np.diff(t))) if len(t) > 1 else 1.0 / (8 * f)
    per_period = 1.0 / (f * dt)
    periods = max(1, math.ceil(MIN_FIT_SAMPLES / per_period - 1e-9))
    expected = int(periods * per_period + 1e-6)
    windows = np.floor((t - seg.t_ref) * f / periods + 1e-9).astype(int)
    return windows, periods, expected


@dataclass
class _Window:
    coef: tuple     # (c, a, s) of the poses, each (6,)
    load: tuple     # (c, a, s) of the load
    n: int
    amplitude: float
    t0: float       # start [s]


def _harmonic_windows(data, poses, seg):
    """Per-window sine fits of a harmonic segment's steady part (full windows only)."""
    windows, periods, expected = _windows(data, seg)
    omega = 2 * np.pi * seg.frequency_hz
    t = data.t[seg.read_start:seg.read_stop]
    p = poses[seg.read_start:seg.read_stop]
    force = data.force[seg.read_start:seg.read_stop]
    need = max(MIN_FIT_SAMPLES, math.ceil(0.75 * expected))
    span = periods / seg.frequency_hz
    out = []
    for k in np.unique(windows):
        sel = windows == k
        tau = t[sel] - seg.t_ref
        if sel.sum() < need:
            continue
        start = k * span
        if tau[0] - start > 0.25 * span or start + span - tau[-1] > 0.25 * span + span / expected:
            continue   # the window is not covered (the test's last, cut-off one)
        c, a, s = fit_sine(tau, p[sel], omega)
        lc, la, ls = fit_sine(tau, force[sel][:, None], omega)
        out.append((k, _Window((c, a, s), (lc[0], la[0], ls[0]), int(sel.sum()),
                               float(np.hypot(a[1], s[1])), float(seg.t_ref + start))))
    return out


def _trend_t(y):
    """|t-statistic| of the slope of a least-squares line through y (equally spaced)."""
    n = len(y)
    x = np.arange(n) - (n - 1) / 2.0
    sxx = float(x @ x)
    slope = float(x @ (y - y.mean())) / sxx
    resid = y - y.mean() - slope * x
    se = math.sqrt(max(float(resid @ resid) / (n - 2), 0.0) / sxx)
    return abs(slope) / se if se > 0 else (0.0 if slope == 0 else math.inf)


def _window_axes(windows, q0):
    """Per window the mean (beta, b) of its two peaks (beta unwrapped against the first)."""
    out = []
    for _, w in windows:
        axes = [axis_of_pose(pose, q0) for pose in peak_poses(*w.coef)]
        out.append([unwrap_axis(a.beta, a.b, axes[0].beta) for a in axes])
    values = np.array(out).mean(axis=1)
    ref = values[0, 0]
    for i, (beta, b) in enumerate(values):
        values[i] = unwrap_axis(beta, b, ref)
    return values


def _steady(windows, q0, t_steady):
    """The windows of a steady response: from ``t_steady`` [s] on (the load at full amplitude,
    plus the build-up time of a resonance) and from the first window after which neither the
    axis angle beta nor the arm b of the windows has a trend (slope |t| < TREND_T; a
    transient of another mode drifts the axis as it dies out)."""
    windows = [(k, w) for k, w in windows if w.t0 >= t_steady - 1e-9]
    if len(windows) < MIN_TREND_WINDOWS:
        return windows
    axes = _window_axes(windows, q0)
    last = len(windows) - max(MIN_TREND_WINDOWS, len(windows) // 4)
    for first in range(0, last + 1):
        if all(_trend_t(axes[first:, i]) < TREND_T for i in (0, 1)):
            return windows[first:]
    return windows[last:]


def _resonance_wait(frequency_hz, poles):
    """Build-up time [s] of a harmonic test at a resonance of a measured pole (within its
    half-power band): ONSET_TIME_CONSTANTS / (zeta omega_n), as the virtual bench waits."""
    wait = 0.0
    for p in poles:
        f_i = p.omega_n / (2 * np.pi)
        if p.zeta > 0 and abs(f_i - frequency_hz) <= 2.0 * p.zeta * f_i:
            wait = max(wait, ONSET_TIME_CONSTANTS / (p.zeta * p.omega_n))
    return wait


def _harmonic_reading(name, kind, seg, windows, q0):
    length = float(np.hypot(q0[0], q0[2]))
    mean = RunningMean(length, BAND_LENGTH_M, BAND_ANGLE_RAD, SETTLE_PEAKS)
    for _, w in windows:
        for pose in peak_poses(*w.coef):
            axis = axis_of_pose(pose, q0)
            mean.add(axis.l, axis.beta, axis.b)
    n = sum(w.n for _, w in windows)
    return HarmonicReading(name, kind, seg.frequency_hz, np.array(mean.values).reshape(-1, 3),
                           mean.settled, n, length)


def _uniform(t, values):
    """Values resampled on a uniform grid of the median interval (missing frames filled by a
    cubic spline through the others); (values, dt, frames filled)."""
    dt = float(np.median(np.diff(t)))
    n = int(round((t[-1] - t[0]) / dt)) + 1
    grid = t[0] + dt * np.arange(n)
    index = np.rint((t - t[0]) / dt).astype(int)
    on_grid = np.all(np.abs(t - grid[np.clip(index, 0, n - 1)]) <= 1e-6 * dt)
    if on_grid and len(t) == n:
        return values, dt, 0
    from scipy.interpolate import CubicSpline
    return CubicSpline(t, values, axis=0)(grid), dt, n - len(t)


def _decay_reading(data, poses, seg, q0, noise_m):
    """DecayReading of a release, or (None, reason) when the markers do not swing there."""
    stop = min(seg.read_stop, seg.read_start + MAX_DECAY_FRAMES)
    n = stop - seg.read_start
    if n < MIN_DECAY_FRAMES:
        return None, f"{n} frames after the release (at least {MIN_DECAY_FRAMES})", 0
    p = poses[seg.read_start:stop]
    swing = float(np.ptp(p[:, 1]))
    if not swing > max(DECAY_SWING_FACTOR * noise_m, 1e-12):
        return None, (f"the loaded end hardly moves after the load is removed (lateral swing "
                      f"{swing:.3g} m, a free decay needs {DECAY_SWING_FACTOR:g} x noise_m): "
                      f"an unloading, not a release"), 0
    scale = np.r_[np.ones(3), np.full(3, np.linalg.norm(q0))]
    values, dt, filled = _uniform(data.t[seg.read_start:stop], p * scale)
    poles = decay_poles(values, dt)
    if not poles:
        return None, "no vibration found in the free response (matrix pencil)", filled
    return DecayReading(tuple(poles), len(values), dt), None, filled


# --- omega_n, zeta of the modes ----------------------------------------------------------------

def _harmonic_modal(windows, static, frequency_hz):
    """Single-mode omega_n [rad/s], zeta [-] with variances from a harmonic test's receptance
    per window (module doc), and the lag [deg] of the response; NaN when not a resonance."""
    g0 = static.pose[1] / static.force
    g = []
    for _, w in windows:
        y = w.coef[1][1] - 1j * w.coef[2][1]
        load = w.load[1] - 1j * w.load[2]
        if abs(load) > 0 and abs(y) > 0:
            g.append(g0 / (y / load))
    nan = (math.nan,) * 5
    if len(g) < 2:
        return nan
    g = np.array(g)
    mean, cov = mean_and_covariance(np.column_stack([g.real, g.imag]))
    lag = math.degrees(math.atan2(mean[1], mean[0]))
    if not (RESONANCE_LAG_DEG[0] <= lag <= RESONANCE_LAG_DEG[1]) or 1.0 - mean[0] <= 0:
        return (math.nan, math.nan, math.nan, math.nan, lag)
    omega = 2 * np.pi * frequency_hz

    def modal(v):
        r = math.sqrt(1.0 - v[0])
        return np.array([omega / r, v[1] / (2.0 * r)])

    values, out = propagate(modal, mean, cov, 1e-7 * np.maximum(np.abs(mean), 1e-6))
    if not (abs(values[0] / omega - 1.0) <= RESONANCE_DETUNING and 0.0 < values[1] < MAX_ZETA):
        return (math.nan, math.nan, math.nan, math.nan, lag)
    return float(values[0]), float(values[1]), float(out[0, 0]), float(out[1, 1]), lag


def _half_var(bounds):
    lo, hi = bounds
    if not (math.isfinite(lo) and math.isfinite(hi)):
        return math.nan
    return ((hi - lo) / (2.0 * 1.959963984540054)) ** 2


def _mode_of(test, windows, static, decay):
    """omega_n, zeta, their variances, the source and the modal entry of a model test."""
    omega_test = 2 * np.pi * test.frequency_hz
    pole = match_pole(list(decay.poles), omega_test) if decay else None
    w_h, z_h, wv_h, zv_h, lag = _harmonic_modal(windows, static, test.frequency_hz)
    if pole is not None:
        omega, zeta = pole.omega_n, pole.zeta
        omega_var, zeta_var = _half_var(pole.omega_n_ci), _half_var(pole.zeta_ci)
        source = "free decay"
    elif math.isfinite(w_h):
        omega, zeta, omega_var, zeta_var = w_h, z_h, wv_h, zv_h
        source = f"harmonic response (single mode, lag {lag:.1f} deg)"
    else:
        omega, zeta, omega_var, zeta_var = omega_test, math.nan, 0.0, math.nan
        source = ("test frequency (not in the free decay; the harmonic response lags by "
                  f"{lag:.1f} deg: no resonance, zeta undefined)")
    nan2 = [math.nan, math.nan]
    entry = {"f_hz": omega / (2 * np.pi), "omega_n": omega, "zeta": zeta,
             "omega_n_decay": pole.omega_n if pole else None,
             "zeta_decay": pole.zeta if pole else None,
             "omega_n_harmonic": w_h, "zeta_harmonic": z_h, "source": source,
             "ci": {"omega_n": interval(omega, omega_var), "zeta": interval(zeta, zeta_var),
                    "omega_n_decay": list(pole.omega_n_ci) if pole else nan2,
                    "zeta_decay": list(pole.zeta_ci) if pole else nan2,
                    "omega_n_harmonic": interval(w_h, wv_h), "zeta_harmonic": interval(z_h, zv_h),
                    "level": LEVEL, "n_bootstrap": pole.n_bootstrap if pole else 0,
                    "n_bootstrap_found": pole.n_found if pole else 0}}
    return omega, zeta, omega_var, zeta_var, entry


# --- the identification ------------------------------------------------------------------------

def _pick_models(harmonics, decay):
    """{label: segment name} of the torsion and bending tests among the harmonic tests
    (labelled ones by their label; else by their axis, nearest a decay pole first, then the
    lowest frequency)."""
    chosen = {name: name for name, (seg, _, _, _) in harmonics.items()
              if seg.labelled and name in MODEL_LABELS}
    poles = [p.omega_n for p in decay.poles] if decay else []

    def distance(item):
        seg = item[1][0]
        omega = 2 * np.pi * seg.frequency_hz
        near = min((abs(p - omega) / omega for p in poles), default=math.inf)
        return (near > 0.05, near, seg.frequency_hz)

    for label in MODEL_LABELS:
        if label in chosen:
            continue
        candidates = [(n, h) for n, h in harmonics.items()
                      if not h[0].labelled and label_axis(h[3]) == label]
        if candidates:
            chosen[label] = min(candidates, key=distance)[0]
    return chosen


def _static_test(data, poses, segments, ref_frames):
    """(the static tests, the one used, its StaticReading): the one named 'static', else the
    first; MeasurementError when the record has none."""
    statics = [s for s in segments if s.kind == "static"]
    if not statics:
        found = ", ".join(f"{s.name} ({s.kind})" for s in segments) or "none"
        raise MeasurementError(data.source, f"no static test (a ramp to a load held for at "
                                            f"least 10 frames) in the record; eq. (8) needs "
                                            f"F_st and y_st of one (tests found: {found})",
                               column="fy")
    static_seg = next((s for s in statics if s.name == "static"), statics[0])
    return statics, static_seg, _static_reading(data, poses, static_seg, ref_frames)


def _free_decay(data, poses, segments, q0, noise_m, report):
    """(DecayReading, its segment, frames filled) of the longest free decay, or Nones; every
    decay segment's entry appended to ``report``."""
    decay, decay_seg, filled = None, None, 0
    for seg in (s for s in segments if s.kind == "decay"):
        reading, reason, n_filled = _decay_reading(data, poses, seg, q0, noise_m)
        entry = seg.summary(data.t)
        if reading is None:
            entry["used"] = False
            entry["note"] += f"; not a free decay: {reason}"
        elif decay is None or reading.n_samples > decay.n_samples:
            decay, decay_seg, filled = reading, seg, n_filled
            entry["used"] = True
        report.append(entry)
    return decay, decay_seg, filled


def _harmonic_tests(data, poses, segments, q0, decay, report):
    """({name: (segment, windows, HarmonicReading, beta)} of the harmonic tests with a steady
    response, [AxisModel] of the sweep's steps); every entry appended to ``report``."""
    harmonics, sweep = {}, []
    for seg in (s for s in segments if s.kind in ("harmonic", "sweep")):
        wait = _resonance_wait(seg.frequency_hz, decay.poles if decay else ())
        windows = _steady(_harmonic_windows(data, poses, seg), q0,
                          float(data.t[seg.read_start]) + wait)
        entry = seg.summary(data.t)
        if len(windows) < 1:
            entry.update(used=False, note=entry["note"] + "; no full window of a steady "
                                                          "response")
            report.append(entry)
            continue
        reading = _harmonic_reading(seg.name, seg.kind, seg, windows, q0)
        entry.update(used=True, windows=len(windows), t_read=windows[0][1].t0,
                     resonance_wait_s=wait)
        report.append(entry)
        if seg.kind == "sweep":
            values, _, ci, info = harmonic_axis(reading)
            sweep.append(AxisModel({"f_hz": float(seg.frequency_hz), **values}, ci, info))
            continue
        beta = harmonic_axis(reading)[0]["beta"]
        harmonics[seg.name] = (seg, windows, reading, beta)
    return harmonics, sweep


def _mode_models(name, harmonics, chosen, static_reading, decay, report):
    """({label: AxisModel}, {label: covariance}, modal entries) of the torsion and bending
    tests ``chosen`` (eqs. 8-11); the report's entry of each test gets its model label."""
    models, covs, modal = {}, {}, {}
    for label in MODEL_LABELS:
        if label not in chosen:
            continue
        seg, windows, reading, _ = harmonics[chosen[label]]
        reading = HarmonicReading(label, "harmonic", reading.frequency_hz, reading.peaks,
                                  reading.settled, reading.n_samples, reading.length)
        omega, zeta, omega_var, zeta_var, modal[label] = _mode_of(seg, windows, static_reading,
                                                                  decay)
        models[label], covs[label] = mode_model(reading, static_reading, omega, zeta,
                                                omega_var, zeta_var)
        check_positive_k(name, label, models[label])
        for e in report:
            if e["name"] == seg.name:
                e["model"] = label
    modal["n_samples_decay"] = decay.n_samples if decay else 0
    return models, covs, modal


def _other_axes(harmonics, chosen):
    """{name: AxisModel} of the harmonic tests that are neither the torsion nor the bending one."""
    out = {}
    for name, (seg, _, reading, _) in harmonics.items():
        if name not in chosen.values():
            values, _, ci, info = harmonic_axis(reading)
            out[name] = AxisModel({"f_hz": float(seg.frequency_hz), **values}, ci, info)
    return out


def _stiffness_split(static, static_cov, models, covs, notes):
    """k_t, k_b by eq. (12) when both mode models exist, else NaN with the reason in ``notes``."""
    if "torsion" in models and "bending" in models:
        return split_model(static.values, static_cov, models["torsion"].values,
                           covs["torsion"], models["bending"].values, covs["bending"])
    missing = " and ".join(label for label in MODEL_LABELS if label not in models)
    problem = (f"no {missing} test in the measurements (a harmonic test whose axis is "
               f"within 45 deg of O-q0 is the torsion test, else the bending test)")
    notes.append(problem)
    return AxisModel({"k_t": math.nan, "k_b": math.nan},
                     {"k_t": [math.nan] * 2, "k_b": [math.nan] * 2},
                     {"split_identifiable": False, "split_problem": problem})


def _static_entries(data, statics, static_seg):
    """The report's entries of the static tests: the one used and the others."""
    entries = [static_seg.summary(data.t) | {"used": True, "model": "static"}]
    for seg in statics:
        if seg is not static_seg:
            entries.append(seg.summary(data.t) | {"used": False,
                                                  "note": "another static test (the first "
                                                          "one is used)"})
    return entries


def _principal(data, poses, bench, ref_frames, static_seg, static_reading, report):
    """The principal hinges from the static test and the moment tests (their entries appended
    to ``report``), the loads as measured."""
    moment_readings, units, moment_report = _moment_tests(data, poses, bench.q0, ref_frames)
    report += moment_report
    sel = slice(static_seg.read_start, static_seg.read_stop)
    units["static"] = data.wrench[sel].mean(axis=0) / static_reading.force
    return identify_principal({"static": static_reading, **moment_readings}, bench.q0,
                              bench.carried, units)


def identify_measured(data, bench):
    """MeasuredIdentification of Measurements ``data`` with a BenchFile (module doc).

    MeasurementError (naming the file, the row and the column) when the data cannot give an
    identification: no static test, markers that do not fit the reference, too few frames
    before the first load for ``markers: from_data``.
    """
    q0 = bench.q0
    segments, noise, threshold = find_tests(data.t, data.force, data.labels, data.source)
    segments = [s for s in segments if not (s.labelled and s.name in MOMENT_TESTS)]
    loaded = np.flatnonzero(np.abs(data.force) > threshold)
    reference, ref_frames, ref_text = _reference(data, bench, int(loaded[0]))
    poses, residual = fit_poses(data.markers, reference, q0)
    _check_rigid(data, bench, residual, ref_text)
    statics, static_seg, static_reading = _static_test(data, poses, segments, ref_frames)
    static, static_cov = static_model(static_reading, q0)
    check_positive_k(bench.name, "static", static)
    notes, report = [], []
    decay, decay_seg, filled = _free_decay(data, poses, segments, q0, bench.noise_m, report)
    harmonics, sweep = _harmonic_tests(data, poses, segments, q0, decay, report)
    chosen = _pick_models(harmonics, decay)
    models, covs, modal = _mode_models(bench.name, harmonics, chosen, static_reading, decay,
                                       report)
    split = _stiffness_split(static, static_cov, models, covs, notes)
    for label, model in models.items():
        if not math.isfinite(model["c"]):
            notes.append(f"{label}: c not identified ({modal[label]['source']})")
    report += _static_entries(data, statics, static_seg)
    principal = _principal(data, poses, bench, ref_frames, static_seg, static_reading, report)
    report.sort(key=lambda e: e["t_start"])
    measured = {"source": data.source, "bench": bench.source, "reference": ref_text,
                "frames": len(data.t), "markers": data.n_markers,
                "counts": dict(data.counts) | {"decay_frames_filled": filled},
                "load_noise_n": noise, "load_threshold_n": threshold,
                "rigid_fit_residual_m": float(np.median(residual)),
                "decay_test": decay_seg.name if decay_seg else None,
                "tests": report, "notes": notes}
    return MeasuredIdentification(bench.name, static, models.get("torsion"),
                                  models.get("bending"), split, tuple(sweep), modal,
                                  _other_axes(harmonics, chosen), principal, measured)
