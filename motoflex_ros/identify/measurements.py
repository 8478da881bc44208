"""Measurements of a bench as the identification reads them: load and marker streams and the
synchronisation of the two streams by their stamps.

A rig has two sensors: the load cell (a wrench per sample, stamped) and the marker sensor
(motion capture or lasers: a set of marker positions per frame, stamped). They run at their
own rates and clocks. :func:`synchronise` turns them into one :class:`Measurements` table, one
row per marker frame: the frame's capture time is its stamp minus the sensor latency, and the
load at that instant is interpolated linearly between the two load samples around it
(approximate-time matching; a frame with no load sample close enough on both sides, in a gap of
the load cell or outside its record, is left out and counted as unmatched). Frames missing from
a stream are counted from its stamps (:func:`dropouts`).

The CSV file of a real rig is read and written in
:mod:`motoflex_ros.formats.measured_csv`; every problem with a measurement is one
:class:`MeasurementError` naming the file, the row and the column.
"""
import math
import warnings
from dataclasses import dataclass, field

import numpy as np

from motoflex_ros.errors import MotoflexError
from motoflex_ros.units import NS_PER_S

__all__ = ["MeasurementError", "row_text", "check_increasing", "LoadStream", "MarkerStream",
           "Measurements", "marker_columns", "synchronise", "check_time_resolution",
           "dropouts", "typical_intervals", "interval_context", "MIN_MARKERS", "RATE_CHANGE",
           "DROPOUT_FACTOR", "PAUSE_FACTOR", "frames_of_marker_sets", "frames_of_marker_streams",
           "stream_measurements", "live_measurements"]

MIN_MARKERS = 3
DROPOUT_FACTOR = 1.5   # an interval longer than 1.5 typical ones has lost frames...
PAUSE_FACTOR = 5.0     # ... up to 5 typical ones; a longer one is a pause between tests
BRIDGE_FACTOR = 3.5    # a load is interpolated across at most 3.5 typical load intervals
MEDIAN_WINDOW = 9      # intervals around each one whose median is its typical interval
RATE_CHANGE = 0.1      # sampling intervals 10 % apart: another rate
TIME_RESOLUTION = 0.01     # coarsest stored time step, as a share of the sampling interval


class MeasurementError(MotoflexError):
    """Measured data the identification cannot use; the message names the file, the row (or
    message) and the column (or field)."""

    def __init__(self, source, problem, row=None, column=None, unit="row"):
        where = str(source)
        if row == 0:
            where += ": header"
        elif row is not None:
            where += f": {row_text(row, unit)}"
        if column is not None:
            where += f"{',' if row is not None else ':'} column '{column}'"
        self.source, self.row, self.column = str(source), row, column
        super().__init__(f"{where}: {problem}")


def row_text(row, unit="row"):
    """'row 5 (line 6)' of data row 5 of a CSV file (the header is line 1), else 'message 5'."""
    return f"row {row} (line {row + 1})" if unit == "row" else f"{unit} {row}"


def marker_columns(n):
    """CSV column names m1_x, m1_y, m1_z, ... of ``n`` markers."""
    return [f"m{i}_{axis}" for i in range(1, n + 1) for axis in "xyz"]


@dataclass(frozen=True)
class LoadStream:
    """Load-cell samples: stamps t (n,) [s] and wrenches (n, 6) [N, N m] (fx, fy, fz, mx, my,
    mz at the loaded end, clamp frame); ``rows`` the sample's row or message number."""

    t: np.ndarray
    wrench: np.ndarray
    source: str = "loads"
    rows: np.ndarray = None
    row_unit: str = "row"


@dataclass(frozen=True)
class MarkerStream:
    """Marker frames: stamps t (n,) [s] and positions (n, N, 3) [m] (clamp frame)."""

    t: np.ndarray
    markers: np.ndarray
    source: str = "markers"
    rows: np.ndarray = None
    row_unit: str = "row"


@dataclass(frozen=True)
class Measurements:
    """Synchronised measurements, one row per marker frame: capture time t (n,) [s], the load
    at that time (n, 6) [N, N m], the markers (n, N, 3) [m], test labels (n,) ('' none),
    the source row or message of each frame and counts of what the synchronisation found
    (frames, dropped and unmatched ones)."""

    source: str
    t: np.ndarray
    wrench: np.ndarray
    markers: np.ndarray
    labels: tuple
    rows: np.ndarray
    counts: dict = field(default_factory=dict)
    row_unit: str = "row"

    @property
    def n_markers(self):
        """Markers per frame."""
        return self.markers.shape[1]

    @property
    def force(self):
        """Lateral load F_y (n,) [N]."""
        return self.wrench[:, 1]

    def where(self, i):
        """'row R (line L)' (CSV) or 'message M' (a bag's or a live rig's marker message) of
        frame i."""
        return row_text(int(self.rows[i]), self.row_unit)


def typical_intervals(t):
    """Median of the MEDIAN_WINDOW intervals around each interval of the stamps t (n,) [s];
    (n - 1,)."""
    dt = np.diff(np.asarray(t, float))
    if len(dt) == 0:
        return dt
    half = MEDIAN_WINDOW // 2
    padded = np.pad(dt, half, mode="edge")
    windows = np.lib.stride_tricks.sliding_window_view(padded, MEDIAN_WINDOW)
    return np.median(windows, axis=1)


def interval_context(t):
    """Per interval of the stamps t (n,) [s]: its length and the medians of the four intervals
    before and of the four after it (its own length where there are none); three (n - 1,)."""
    dt = np.diff(np.asarray(t, float))
    if len(dt) == 0:
        return dt, dt, dt
    pad = np.full(4, np.nan)
    windows = np.lib.stride_tricks.sliding_window_view(np.r_[pad, dt, pad], 4)
    with warnings.catch_warnings():   # all-NaN windows at the ends: replaced below
        warnings.simplefilter("ignore", RuntimeWarning)
        before = np.nanmedian(windows[:len(dt)], axis=1)      # dt[i-4:i]
        after = np.nanmedian(windows[5:5 + len(dt)], axis=1)  # dt[i+1:i+5]
    return dt, np.where(np.isnan(before), dt, before), np.where(np.isnan(after), dt, after)


def dropouts(t):
    """Samples missing from stamps t [s]: an interval of 1.5 to 5 typical intervals (the
    sampling rate the same before and after it, within RATE_CHANGE) has lost
    round(interval / typical) - 1 samples; a longer one, or one where the rate changes, is a
    pause between tests."""
    dt, before, after = interval_context(t)
    if len(dt) < 3:
        return 0
    typical = np.minimum(before, after)
    ratio = dt / typical
    same_rate = np.abs(after / before - 1.0) <= RATE_CHANGE
    lost = (ratio > DROPOUT_FACTOR) & (ratio <= PAUSE_FACTOR) & same_rate
    return int(np.sum(np.rint(ratio[lost]) - 1))


def check_increasing(t, source, rows, column="t", unit="row"):
    """MeasurementError at the first stamp t [s] that is not after the one before."""
    bad = np.flatnonzero(np.diff(t) <= 0.0)
    if len(bad):
        i = int(bad[0]) + 1
        raise MeasurementError(source, f"t = {t[i]:.9g} s is not after the previous "
                                       f"{t[i - 1]:.9g} s (time must increase from {unit} to "
                                       f"{unit})", int(rows[i]), column, unit)


def synchronise(loads, markers, latency_s=0.0, labels=None):
    """Measurements at the marker frames' capture times (stamp - latency_s [s]).

    The load at each frame is interpolated between the load samples around it (exact where a
    load stamp equals the capture time); frames outside the load record or in a gap of more
    than BRIDGE_FACTOR typical load intervals are unmatched (left out, counted). ``labels``:
    per marker frame, or None.
    """
    tl, wl = np.asarray(loads.t, float), np.asarray(loads.wrench, float)
    tc = np.asarray(markers.t, float) - float(latency_s)
    n = len(tc)
    j = np.searchsorted(tl, tc, side="right") - 1
    exact = (j >= 0) & (tl[np.clip(j, 0, len(tl) - 1)] == tc)
    inside = (j >= 0) & (j < len(tl) - 1)
    ok = exact.copy()
    wrench = np.zeros((n, 6))
    wrench[exact] = wl[j[exact]]
    if len(tl) >= 2:
        typical = typical_intervals(tl)
        jj = np.clip(j, 0, len(tl) - 2)
        gap = tl[jj + 1] - tl[jj]
        bridge = inside & ~exact & (gap <= BRIDGE_FACTOR * typical[jj])
        w = ((tc - tl[jj]) / np.where(gap > 0, gap, 1.0))[bridge]
        wrench[bridge] = (1.0 - w)[:, None] * wl[jj[bridge]] + w[:, None] * wl[jj[bridge] + 1]
        ok |= bridge
    rows = markers.rows if markers.rows is not None else np.arange(1, n + 1)
    keep = np.flatnonzero(ok)
    labels = tuple(labels[i] for i in keep) if labels is not None else ("",) * len(keep)
    counts = {"marker_frames": n, "load_samples": len(tl), "frames": len(keep),
              "unmatched_frames": int(n - len(keep)),
              "dropped_marker_frames": dropouts(markers.t),
              "dropped_load_samples": dropouts(tl)}
    return Measurements(f"{markers.source} + {loads.source}", tc[keep], wrench[keep],
                        np.asarray(markers.markers, float)[keep], labels,
                        np.asarray(rows)[keep], counts, markers.row_unit)


# --- CSV -----------------------------------------------------------------------------------

def check_time_resolution(t, source, rows, unit="row"):
    """MeasurementError when the stamps t [s] are so large that a double stores them coarser
    than TIME_RESOLUTION of the mean sampling interval (times shifted by 1e12 s keep only
    0.1 ms: the intervals, and the decay tests with them, are lost)."""
    if len(t) < 2:
        return
    step = (t[-1] - t[0]) / (len(t) - 1)
    coarse = float(np.spacing(np.max(np.abs(t))))
    if not coarse <= TIME_RESOLUTION * step:
        raise MeasurementError(source, f"times up to {np.max(np.abs(t)):.6g} s are stored to "
                                       f"{coarse:.2g} s only, more than {TIME_RESOLUTION:g} of "
                                       f"the mean sampling interval {step:.3g} s: give t from "
                                       f"the start of the record (subtract the first time)",
                               int(rows[np.argmax(np.abs(t))]), "t", unit)


# --- frames from marker messages (a bag's or a live rig's) ---------------------------------

def frames_of_marker_sets(sets, n_markers, source):
    """Marker frames of PoseArray-like messages: ``sets`` [(stamp [ns], points (k N, 3),
    message number)]; a message with k sets of N markers is k frames, its last at its stamp,
    the others back at the stream's typical interval (frames that would not come after the
    previous message's are left out). N: ``n_markers`` or the most common set size.

    Returns (stamps [ns] (n,), frames (n, N, 3), message numbers (n,), frames left out).
    """
    sets = [(int(ns), np.asarray(p, float).reshape(-1, 3), i) for ns, p, i in sets]
    sizes = [len(p) for _, p, _ in sets if len(p)]
    if not sizes:
        raise MeasurementError(source, "no marker sets")
    n = n_markers or int(np.bincount(sizes).argmax())
    if n < MIN_MARKERS:
        raise MeasurementError(source, f"{n} markers per frame, at least {MIN_MARKERS} needed "
                                       f"(a rigid fit of the loaded end)")
    full = []
    for ns, points, i in sets:
        if len(points) % n:
            raise MeasurementError(source, f"{len(points)} poses, not a whole number of "
                                           f"frames of {n} markers", i, "poses",
                                   unit="message")
        if len(points):
            full.append((ns, points.reshape(-1, n, 3), i))
    stamps = np.array([ns for ns, _, _ in full], np.int64)
    check_increasing(stamps.astype(float), source, np.array([i for _, _, i in full]),
                     "header.stamp", "message")
    typical = typical_intervals(stamps.astype(float)) if len(stamps) > 1 else np.zeros(1)
    out, frames, rows, left_out, last = [], [], [], 0, -math.inf
    for j, (ns, points, i) in enumerate(full):
        dt = typical[min(j, len(typical) - 1)]
        k = len(points)
        for m in range(k):
            t = ns - (k - 1 - m) * dt
            if t > last:
                out.append(t)
                frames.append(points[m])
                rows.append(i)
                last = t
            else:
                left_out += 1
    return np.array(out), np.array(frames), np.array(rows), left_out


def frames_of_marker_streams(streams, source):
    """Marker frames assembled from one stream per marker, ``streams`` [(stamps [ns] (n_i,),
    points (n_i, 3))]: at each of marker 1's stamps, each marker's sample nearest to it
    within half a frame interval; frames missing a marker are left out.

    Returns (stamps [ns], frames (n, N, 3), frame numbers of marker 1, frames left out)."""
    if len(streams) < MIN_MARKERS:
        raise MeasurementError(source, f"{len(streams)} marker stream(s), at least "
                                       f"{MIN_MARKERS} needed (one per marker)")
    base = np.asarray(streams[0][0], np.int64)
    if len(base) == 0:
        raise MeasurementError(source, "no marker frames")
    half = 0.5 * typical_intervals(base.astype(float))
    half = np.r_[half, half[-1:]] if len(half) else np.zeros(1)
    frames = np.zeros((len(base), len(streams), 3))
    ok = np.ones(len(base), bool)
    for m, (stamps, points) in enumerate(streams):
        stamps = np.asarray(stamps, np.int64)
        if len(stamps) == 0:
            raise MeasurementError(source, f"marker {m + 1}: no messages")
        j = np.searchsorted(stamps, base)
        before = np.clip(j - 1, 0, len(stamps) - 1)
        after = np.clip(j, 0, len(stamps) - 1)
        near = np.where(np.abs(stamps[before] - base) <= np.abs(stamps[after] - base),
                        before, after)
        ok &= np.abs(stamps[near] - base) <= half
        frames[:, m] = np.asarray(points, float)[near]
    return base[ok], frames[ok], np.flatnonzero(ok) + 1, int(np.sum(~ok))


def stream_measurements(load_ns, wrench, frame_ns, frames, rows, latency_s, load_source,
                        marker_source, counts=None):
    """Measurements of a load stream (stamps [ns], wrenches (n, 6)) and marker frames (stamps
    [ns], (m, N, 3)), times from the earlier first stamp, synchronised after the latency."""
    load_ns = np.asarray(load_ns, np.int64)
    if len(load_ns) == 0:
        raise MeasurementError(load_source, "no load samples")
    check_increasing(load_ns.astype(float), load_source, np.arange(1, len(load_ns) + 1),
                     "header.stamp", "message")
    t0 = min(int(load_ns[0]), int(np.min(frame_ns)))
    loads = LoadStream((load_ns - t0) / NS_PER_S, np.asarray(wrench, float), load_source)
    markers = MarkerStream((np.asarray(frame_ns, float) - t0) / NS_PER_S, frames, marker_source,
                           np.asarray(rows), "message")
    data = synchronise(loads, markers, latency_s)
    data.counts.update(counts or {}, t0_ns=t0)
    return data


def live_measurements(load_ns, wrench, markers, per_marker, bench, source):
    """Measurements of what a live rig sent: load stamps [ns] and wrenches, and the marker
    messages (per_marker: one list of (stamp [ns], point) per marker; else a list of (stamp
    [ns], points) marker sets)."""
    if per_marker:
        streams = [(np.array([s for s, _ in m], np.int64), np.array([p for _, p in m], float))
                   for m in markers]
        stamps, frames, rows, left = frames_of_marker_streams(streams, source)
        extra = {"incomplete_marker_frames": left}
    else:
        sets = [(ns, points, i + 1) for i, (ns, points) in enumerate(markers)]
        stamps, frames, rows, left = frames_of_marker_sets(sets, bench.n_markers, source)
        extra = {"burst_frames_left_out": left}
    for name, values in (("load", wrench), ("markers", frames)):
        bad = np.argwhere(~np.isfinite(np.asarray(values, float)))
        if len(bad):
            raise MeasurementError(source, f"a {name} value is not a finite number",
                                   int(bad[0][0]) + 1, unit="message")
    return stream_measurements(load_ns, wrench, stamps, frames, rows, bench.latency_s,
                               f"{source}: load", f"{source}: markers", extra)
