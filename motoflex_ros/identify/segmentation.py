"""The tests of a measured bench record, found from its load history.

A real rig's record is a load history F_y(t) with the marker frames that go with it; it may
carry test labels (the CSV's ``test`` column) or none. The tests of the paper's campaign
(Passigato et al. 2023, Sect. 4.2) have loads that tell them apart:

- static: a ramp to a load that is then held (``hold``: the frames at the held load);
- harmonic: a sinusoidal load of constant frequency (the frequency and phase are fitted to the
  load; ``steady``: from the first period at full amplitude);
- sweep: three or more harmonic tests in a row at the same amplitude (within
  SWEEP_AMPLITUDE_TOL) with rising or falling frequencies, one after the other or with pauses;
- free decay: a held load released to zero (``release``: the frames after the load has
  dropped, up to the next load, a pause or the end of the record). Whether the structure
  vibrates there (a release, not a slow unloading) is decided on the markers
  (:mod:`motoflex_ros.identify.measured`).

Where tests start and end: at pauses of the record (an interval of more than PAUSE_FACTOR
typical intervals, or of more than DROPOUT_FACTOR where the sampling rate changes, as between
the tests of the virtual bench), at quiet stretches (the load within its noise band for at
least QUIET_MIN_FRAMES frames and QUIET_MIN_S), at changes of the frequency of a sinusoid (a
stepped sweep without pauses) and, in a labelled record, where the label changes. The load's
noise is estimated from the data (:func:`load_noise`); the load counts as applied where it
exceeds both LOAD_NOISE_FACTOR times that noise and LOAD_FLOOR times its largest value.
"""
import math
from dataclasses import dataclass, replace

import numpy as np

from motoflex_ros.identify.measurements import (
    DROPOUT_FACTOR,
    PAUSE_FACTOR,
    RATE_CHANGE,
    MeasurementError,
    interval_context,
)
from motoflex_ros.identify.results import MEASURED_KEY, RESULT_KEYS

__all__ = ["Segment", "find_tests", "load_noise", "load_threshold", "fit_sinusoid",
           "LOAD_NOISE_FACTOR", "LOAD_FLOOR", "QUIET_MIN_FRAMES", "QUIET_MIN_S", "MIN_HOLD",
           "MIN_HALF_PERIODS", "FREQUENCY_TOL", "SWEEP_AMPLITUDE_TOL", "HOLD_TOL"]

LOAD_NOISE_FACTOR = 6.0   # applied load: above 6 x its noise (a noise sample exceeds it 2e-9)
LOAD_FLOOR = 1e-3         # ... and above 1e-3 of the largest load (noise-free records)
QUIET_MIN_FRAMES = 3      # a quiet stretch separates tests if it lasts 3 frames...
QUIET_MIN_S = 0.02        # ... and 20 ms (a sine's zero crossing is far shorter above 1 Hz)
MIN_HOLD = 10             # frames at the held load a static test needs
HOLD_TOL = 1e-3           # held load: within 0.1 % of the hold level (or 4 x the noise)
MIN_HALF_PERIODS = 6      # a harmonic test has at least three periods
FREQUENCY_TOL = 0.05      # a new frequency: half periods 5 % off, three in a row
STEADY_LOAD_TOL = 2e-4    # steady: load amplitude within 0.02 % of its largest (or 4 x noise)
SWEEP_AMPLITUDE_TOL = 0.05
NOISE_BLOCK = 32          # frames per block of the noise estimate


@dataclass(frozen=True)
class Segment:
    """One test found in the record: name, kind ('static', 'harmonic', 'sweep', 'decay'),
    frames [start, stop) and the frames read [read_start, read_stop) (hold, steady part or
    release); frequency_hz [Hz], amplitude_n [N] (held load, amplitude or preload), t_ref [s]
    (a harmonic load's upward zero crossing: its windows start there), whether a label named
    it, and a note (how it was found)."""

    name: str
    kind: str
    start: int
    stop: int
    read_start: int
    read_stop: int
    frequency_hz: float = 0.0
    amplitude_n: float = 0.0
    t_ref: float = 0.0
    labelled: bool = False
    note: str = ""

    def summary(self, t):
        """Plain dict for the report (times [s] from the frames' stamps t)."""
        return {"name": self.name, "kind": self.kind, "t_start": float(t[self.start]),
                "t_end": float(t[self.stop - 1]), "t_read": float(t[self.read_start]),
                "frames": self.stop - self.start, "frames_read": self.read_stop - self.read_start,
                "frequency_hz": self.frequency_hz, "amplitude_n": self.amplitude_n,
                "labelled": self.labelled, "note": self.note}


def load_noise(force):
    """Noise [N] of a load history: per block of NOISE_BLOCK frames the robust scale of the
    second differences (1.4826 MAD / sqrt(6)), and their median over the blocks at most twice
    the 10th percentile: holds, pauses and slow ramps give the noise floor, sinusoids larger
    values that are passed over."""
    d2 = np.diff(np.asarray(force, float), 2)
    if len(d2) == 0:
        return 0.0
    n = max(1, len(d2) // NOISE_BLOCK)
    blocks = d2[:n * NOISE_BLOCK].reshape(n, -1) if len(d2) >= NOISE_BLOCK else d2[None, :]
    mad = np.median(np.abs(blocks - np.median(blocks, axis=1, keepdims=True)), axis=1)
    scale = 1.4826 * mad / math.sqrt(6.0)
    floor = np.percentile(scale, 10)
    return float(np.median(scale[scale <= 2.0 * floor]))


def load_threshold(force, noise):
    """Load above which a test is running [N] (module doc)."""
    return max(LOAD_NOISE_FACTOR * noise, LOAD_FLOOR * float(np.max(np.abs(force))))


def _runs(mask):
    """[start, stop) of the runs of True in a boolean array."""
    padded = np.r_[False, np.asarray(mask, bool), False]
    edges = np.flatnonzero(np.diff(padded.astype(np.int8)))
    return list(zip(edges[::2].tolist(), edges[1::2].tolist()))


def _check_load_applied(force, noise, source, column):
    """MeasurementError when no LOAD_NOISE_FACTOR-noise excursion lasts three frames."""
    above = np.abs(force) > LOAD_NOISE_FACTOR * noise
    if not any(b - a >= QUIET_MIN_FRAMES for a, b in _runs(above)) or not np.any(force):
        raise MeasurementError(source, f"the load never exceeds its noise (largest |F_y| "
                                       f"{np.max(np.abs(force)):.4g} N, noise {noise:.3g} N; a "
                                       f"test needs at least {QUIET_MIN_FRAMES} frames above "
                                       f"{LOAD_NOISE_FACTOR:g} x the noise): no test to "
                                       f"identify", column=column)


def _block_edges(t):
    """Frame indices where a new block starts (after a pause or a change of sampling rate)."""
    dt, before, after = interval_context(t)
    if len(dt) == 0:
        return [0, len(t)]
    typical = np.minimum(before, after)
    rate_change = np.abs(after / before - 1.0) > RATE_CHANGE
    cut = (dt > PAUSE_FACTOR * typical) | ((dt > DROPOUT_FACTOR * typical) & rate_change)
    return [0, *(np.flatnonzero(cut) + 1).tolist(), len(t)]


def _crossings(t, force, threshold):
    """Zero-crossing times [s] of a load with hysteresis (a sign counts once it passes
    +-threshold), interpolated linearly between the frames around the zero."""
    state, last, out = 0, None, []
    for i, f in enumerate(force):
        sign = 1 if f > threshold else (-1 if f < -threshold else 0)
        if sign == 0:
            continue
        if state and sign != state:
            for k in range(last, i):
                if force[k] * state > 0 >= force[k + 1] * state:
                    out.append(t[k] + (t[k + 1] - t[k]) * force[k] / (force[k] - force[k + 1]))
                    break
        state, last = sign, i
    return np.array(out)


def _frequency_groups(crossings):
    """Runs of crossings [i, j] (indices) with one frequency: a new one starts where three half
    periods in a row are FREQUENCY_TOL off the running median to the same side."""
    half = np.diff(crossings)
    groups, start, kept = [], 0, []
    i = 0
    while i < len(half):
        if len(kept) >= 2:
            ref = float(np.median(kept))
            off = half[i:i + 3] / ref - 1.0
            if abs(off[0]) > FREQUENCY_TOL:
                if len(off) == 3 and np.all(np.abs(off) > FREQUENCY_TOL) and (
                        np.all(off > 0) or np.all(off < 0)):
                    groups.append((start, i))
                    start, kept = i, []
                    continue
                i += 1   # one stray half period (noise at a crossing)
                continue
        kept.append(half[i])
        i += 1
    groups.append((start, len(crossings) - 1))
    return [g for g in groups if g[1] - g[0] >= MIN_HALF_PERIODS]


def fit_sinusoid(tau, force, omega, iterations=8):
    """Least-squares c + A sin(w tau + phi) of a load sampled at tau [s] from w0 = ``omega``
    [rad/s] (Gauss-Newton in w on the linear fit); returns (w [rad/s], A [N], phi [rad], c
    [N])."""
    tau, force = np.asarray(tau, float), np.asarray(force, float)
    w = float(omega)
    for _ in range(iterations):
        design = np.column_stack([np.ones_like(tau), np.cos(w * tau), np.sin(w * tau)])
        (c, a, b), *_ = np.linalg.lstsq(design, force, rcond=None)
        residual = force - design @ np.array([c, a, b])
        slope = tau * (-a * np.sin(w * tau) + b * np.cos(w * tau))
        full = np.column_stack([design, slope])
        step = np.linalg.lstsq(full, residual, rcond=None)[0][3]
        w += step
        if abs(step) <= 1e-13 * w:
            break
    design = np.column_stack([np.ones_like(tau), np.cos(w * tau), np.sin(w * tau)])
    (c, a, b), *_ = np.linalg.lstsq(design, force, rcond=None)
    # a cos + b sin = A sin(w tau + phi): A cos(phi) = b, A sin(phi) = a
    return w, float(math.hypot(a, b)), float(math.atan2(a, b)), float(c)


def _harmonic(t, force, start, stop, crossings, noise):
    """A harmonic Segment of frames [start, stop) whose load crosses zero at ``crossings``;
    ``noise`` [N] of the load."""
    omega0 = math.pi * (len(crossings) - 1) / (crossings[-1] - crossings[0])
    tau = t[start:stop] - t[start]
    w, amp, phi, _ = fit_sinusoid(tau, force[start:stop], omega0)
    period = 2 * math.pi / w
    # upward zero crossing at or before the first frame: windows of whole periods from there
    t_ref = t[start] - ((phi % (2 * math.pi)) / w)
    if t[start] - t_ref > period - 1e-9 * period:
        t_ref += period
    windows = np.floor((t[start:stop] - t_ref) / period + 1e-9).astype(int)
    amplitudes = []
    for k in np.unique(windows):
        sel = windows == k
        if sel.sum() >= 4:
            _, a_k, _, _ = fit_sinusoid(tau[sel], force[start:stop][sel], w, iterations=0)
            amplitudes.append((k, a_k))
    top = max(a for _, a in amplitudes) if amplitudes else amp
    per_window = max(4, len(tau) / max(1, len(amplitudes)))
    tol = max(STEADY_LOAD_TOL, 4.0 * noise * math.sqrt(2.0 / per_window) / max(top, 1e-300))
    steady_window = next((k for k, a in amplitudes if a >= (1 - tol) * top), windows[0])
    read_start = start + int(np.argmax(windows >= steady_window))
    if amplitudes:   # the steady amplitude: over the windows at full load
        amp = float(np.median([a for k, a in amplitudes if k >= steady_window]))
    # the frequency and phase from the steady part alone (the onset is not a pure sine)
    tau = t[read_start:stop] - t[read_start]
    if len(tau) >= 4:
        w, amp_s, phi, _ = fit_sinusoid(tau, force[read_start:stop], w)
        period = 2 * math.pi / w
        t_ref = t[read_start] - ((phi % (2 * math.pi)) / w)
        while t_ref - period >= t[start] - 1e-9 * period:
            t_ref -= period
    return Segment("", "harmonic", start, stop, read_start, stop, w / (2 * math.pi), amp,
                   float(t_ref), note="constant-frequency sinusoid")


def _hold(force, start, stop, noise):
    """[h0, h1) of the longest run of frames at the held level of a one-signed load, and that
    level [N]; (None, None, level) when shorter than MIN_HOLD."""
    segment = force[start:stop]
    peak = segment[np.argmax(np.abs(segment))]
    top = segment[np.abs(segment) >= 0.9 * abs(peak)]
    level = float(np.median(top))
    tol = max(HOLD_TOL * abs(level), 4.0 * noise)
    runs = _runs(np.abs(segment - level) <= tol)
    if not runs:
        return None, None, level
    a, b = max(runs, key=lambda r: r[1] - r[0])
    if b - a < MIN_HOLD:
        return None, None, level
    level = float(np.mean(segment[a:b]))
    return start + a, start + b, level


def _loaded_runs(t, force, start, stop, threshold):
    """[a, b) of the stretches of an unlabelled block where a load is applied, split at quiet
    stretches (QUIET_MIN_FRAMES frames and QUIET_MIN_S), each with the quiet stretch after it
    [b, c) (c = b at the block's end)."""
    loaded = np.abs(force[start:stop]) > threshold
    quiet = [(start + a, start + b) for a, b in _runs(~loaded)
             if b - a >= QUIET_MIN_FRAMES and t[start + b - 1] - t[start + a] >= QUIET_MIN_S]
    bounds, cursor = [], start
    for a, b in quiet:
        if a > cursor:
            bounds.append((cursor, a, b))
        cursor = b
    if cursor < stop:
        bounds.append((cursor, stop, stop))
    out = []
    for a, b, c in bounds:
        idx = np.flatnonzero(loaded[a - start:b - start])
        if len(idx):
            out.append((a + int(idx[0]), a + int(idx[-1]) + 1, c))
    return out


def _sign_changes(force, threshold):
    signs = np.sign(force[np.abs(force) > threshold])
    return int(np.sum(signs[1:] != signs[:-1]))


def _tests_of_run(t, force, a, b, c, threshold, noise):
    """Segments of one loaded run [a, b) followed by the quiet stretch [b, c)."""
    out = []
    if _sign_changes(force[a:b], threshold) >= 4:
        crossings = _crossings(t[a:b], force[a:b], threshold)
        groups = _frequency_groups(crossings) if len(crossings) > MIN_HALF_PERIODS else []
        for n, (i, j) in enumerate(groups):
            lo = a if n == 0 else int(np.searchsorted(t, crossings[i]))
            last = n == len(groups) - 1
            hi = b if last else int(np.searchsorted(t, crossings[groups[n + 1][0]]))
            if hi - lo >= 8:
                out.append(_harmonic(t, force, lo, hi, crossings[i:j + 1], noise))
        return out
    h0, h1, level = _hold(force, a, b, noise)
    if h0 is not None:
        out.append(Segment("", "static", a, b, h0, h1, amplitude_n=level,
                           note="ramp and hold"))
    if c > b:   # the load dropped to zero and stayed there: a release, if the markers swing
        out.append(Segment("", "decay", b, c, b, c, amplitude_n=float(force[b - 1]),
                           note=f"release from {force[b - 1]:.4g} N"))
    return out


def _kind_of_label(name):
    if name == "static" or name.startswith("static"):
        return "static"
    if name.startswith("decay"):
        return "decay"
    if name.startswith("sweep"):
        return "sweep"
    return None


def _labelled(t, force, a, b, name, threshold, noise):
    """The Segment of a labelled stretch [a, b): kind from the name (static*, decay*, sweep*)
    or, for other names, from the load (a sinusoid: harmonic, else static)."""
    kind = _kind_of_label(name)
    if kind == "decay":
        loaded = np.flatnonzero(np.abs(force[a:b]) > threshold)
        r0 = a + (int(loaded[-1]) + 1 if len(loaded) else 0)
        pre = float(force[r0 - 1]) if r0 > a else 0.0
        return Segment(name, "decay", a, b, r0, b, amplitude_n=pre, labelled=True,
                       note="labelled")
    oscillating = _sign_changes(force[a:b], threshold) >= 4
    if kind == "static" or (kind is None and not oscillating):
        h0, h1, level = _hold(force, a, b, noise)
        if h0 is None:
            return None
        return Segment(name, "static", a, b, h0, h1, amplitude_n=level, labelled=True,
                       note="labelled")
    crossings = _crossings(t[a:b], force[a:b], threshold)
    if len(crossings) <= MIN_HALF_PERIODS:
        return None
    seg = _harmonic(t, force, a, b, crossings, noise)
    return replace(seg, name=name, kind=kind or "harmonic", labelled=True, note="labelled")


def _check_label(name, frame, source):
    """MeasurementError for a test label that is a key of the results (ci, modal, ...)."""
    if name in RESULT_KEYS + (MEASURED_KEY,):
        raise MeasurementError(source, f"'{name}' is a key of the results, not a test name "
                                       f"(not allowed: {', '.join(RESULT_KEYS + (MEASURED_KEY,))}"
                                       f"; static, torsion, bending, sweep_NN, decay or any "
                                       f"other name)", frame + 1, "test")


def _mark_sweeps(segments):
    """Runs of >= 3 consecutive harmonic segments at one amplitude with monotonic frequencies
    become the sweep (kind 'sweep')."""
    out = list(segments)
    i = 0
    while i < len(out):
        j = i
        while (j + 1 < len(out) and out[j + 1].kind == "harmonic" and out[i].kind == "harmonic"
               and not out[j + 1].labelled and not out[i].labelled
               and abs(out[j + 1].amplitude_n / out[i].amplitude_n - 1) <= SWEEP_AMPLITUDE_TOL):
            freqs = [s.frequency_hz for s in out[i:j + 2]]
            steps = np.diff(freqs)
            if not (np.all(steps > 0) or np.all(steps < 0)):
                break
            j += 1
        if j - i + 1 >= 3:
            for k in range(i, j + 1):
                out[k] = replace(out[k], kind="sweep", note="stepped frequencies (sweep)")
            i = j + 1
        else:
            i += 1
    return out


def _name(segments):
    """Names of the unlabelled segments: static, decay (then static_2, decay_2...), sweep_00,
    sweep_01... and harmonic_00... (renamed torsion / bending by the identification)."""
    counts, out = {}, []
    taken = {s.name for s in segments if s.labelled}
    for s in segments:
        if s.labelled:
            out.append(s)
            continue
        key = "harmonic" if s.kind == "harmonic" else s.kind
        n = counts.get(key, 0)
        counts[key] = n + 1
        if key in ("static", "decay"):
            name = key if n == 0 else f"{key}_{n + 1}"
        else:
            name = f"{key}_{n:02d}"
        while name in taken:
            name += "_"
        out.append(replace(s, name=name))
    return out


def find_tests(t, force, labels=None, source="measurements", column="fy"):
    """Segments (time order) of a record: frame stamps t (n,) [s], lateral load (n,) [N],
    labels (n,) ('' where none). Returns (segments, noise [N], threshold [N]).

    MeasurementError naming ``source`` and ``column`` when the load never exceeds its noise.
    """
    t, force = np.asarray(t, float), np.asarray(force, float)
    noise = load_noise(force)
    _check_load_applied(force, noise, source, column)
    threshold = load_threshold(force, noise)
    labels = list(labels) if labels is not None else [""] * len(t)
    segments = []
    edges = _block_edges(t)
    for s0, s1 in zip(edges[:-1], edges[1:]):
        # a labelled record: the label's changes split the block too
        cuts = [s0] + [i for i in range(s0 + 1, s1) if labels[i] != labels[i - 1]] + [s1]
        for a, b in zip(cuts[:-1], cuts[1:]):
            if labels[a]:
                _check_label(labels[a], a, source)
                seg = _labelled(t, force, a, b, labels[a], threshold, noise)
                if seg is not None:
                    segments.append(seg)
                continue
            for ra, rb, rc in _loaded_runs(t, force, a, b, threshold):
                segments.extend(_tests_of_run(t, force, ra, rb, rc, threshold, noise))
    segments = _mark_sweeps(segments)
    return _name(segments), noise, threshold
