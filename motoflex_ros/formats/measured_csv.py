"""The measured CSV format of a real rig: read into, and written from, identify's Measurements.

The file has one row per sample and exactly this header::

    t,test,fx,fy,fz,mx,my,mz,m1_x,m1_y,m1_z,m2_x,m2_y,m2_z,...

t [s], forces [N], moments [N m], marker coordinates [m] in the clamp frame (x-z the
component's plane, load along y), N >= 3 markers; ``test`` is a test label or empty. A row
holds the load and the markers of one instant (the markers stamped ``latency_s`` after their
capture, as the bench file says). Every problem is one :class:`MeasurementError` naming the
file, the row and the column.

Written with 17 significant digits, so a file written here reads back exactly.
"""
import csv
import math
from array import array
from pathlib import Path

import numpy as np

from motoflex_ros.files import atomic_write_text, missing_file_text
from motoflex_ros.identify.measurements import (
    MIN_MARKERS,
    LoadStream,
    MarkerStream,
    MeasurementError,
    Measurements,
    check_increasing,
    check_time_resolution,
    dropouts,
    marker_columns,
    synchronise,
)
from motoflex_ros.limits import check_limit, limit

__all__ = ["CSV_HEAD", "read_csv", "write_csv", "write_measured_csv", "MAX_CSV_BYTES",
           "MAX_CSV_LINE", "MAX_MARKERS"]

CSV_HEAD = ("t", "test", "fx", "fy", "fz", "mx", "my", "mz")
WRENCH = CSV_HEAD[2:]
MAX_CSV_BYTES = 2_000_000_000
MAX_CSV_LINE = 1_000_000   # characters of one line (a row of 1,000 markers: about 60,000)
MAX_MARKERS = 1_000        # markers of a CSV header


def _check_header(header, source):
    """Number of markers of a CSV header, or MeasurementError naming the column."""
    header = [h.strip() for h in header]
    if header and header[0].startswith("\ufeff"):
        header[0] = header[0][1:]
    allowed = ",".join(CSV_HEAD) + ",m1_x,m1_y,m1_z,m2_x,..."
    for i, name in enumerate(CSV_HEAD):
        if i >= len(header) or header[i] != name:
            problem = ("missing" if name not in header else
                       f"expected as column {i + 1}, found '{header[i]}' there")
            raise MeasurementError(source, f"{problem} (the header must be exactly {allowed}, "
                                           f"N >= {MIN_MARKERS} markers)", 0, name)
    rest = header[len(CSV_HEAD):]
    n = math.ceil(len(rest) / 3)
    for i, name in enumerate(marker_columns(n)):
        if i >= len(rest) or rest[i] != name:
            found = f"found '{rest[i]}'" if i < len(rest) else "missing"
            raise MeasurementError(source, f"{found} where column {len(CSV_HEAD) + i + 1} "
                                           f"must be '{name}' (marker columns m1_x,m1_y,m1_z,"
                                           f"m2_x,... in order)", 0, name)
    if n > MAX_MARKERS:
        raise MeasurementError(source, f"{n:,} markers in the header, at most {MAX_MARKERS:,}",
                               0, f"m{MAX_MARKERS + 1}_x")
    if n < MIN_MARKERS:
        raise MeasurementError(source, f"{n} marker(s) in the header, at least {MIN_MARKERS} "
                                       f"needed (m1_* to m{MIN_MARKERS}_*): a rigid fit of "
                                       f"the loaded end needs three markers that span a plane",
                               0, f"m{n + 1}_x")
    return n


def _lines(stream, source):
    """The lines of a text stream, each refused past MAX_CSV_LINE characters or with a NUL
    character (a binary or sparse file) before more of the file is read: bounded memory."""
    number = 0
    while True:
        line = stream.readline(MAX_CSV_LINE + 1)
        if not line:
            return
        number += 1
        if len(line) > MAX_CSV_LINE:
            raise MeasurementError(source, f"line {number} is longer than {MAX_CSV_LINE:,} "
                                           f"characters: not a CSV file of measurements")
        if "\0" in line:
            raise MeasurementError(source, f"line {number} holds a NUL character at character "
                                           f"{line.index(chr(0)) + 1}: a binary (or sparse) "
                                           f"file, not a CSV file")
        yield line


def _bad_cell(row, header, index, source):
    """MeasurementError naming the first cell of a data row that is not a finite number."""
    for k, text in enumerate(row):
        if k == 1:
            continue
        try:
            value = float(text)
        except ValueError:
            value = None
        if value is None or not math.isfinite(value):
            shown = "empty" if not text.strip() else f"'{text.strip()[:40]}'"
            return MeasurementError(source, f"{shown} is not a finite number (each of t, "
                                            f"fx..mz and the marker coordinates must be one)",
                                    index, header[k])
    return None


def _data_rows(reader, header, source):
    """(values (n, width - 1) floats without the label column, labels, n) of the data rows,
    parsed as they are read: the row count is checked against the 'samples' limit at every
    row, so a file of millions of rows is refused when its first row past the limit is read."""
    width, allowed = len(header), limit("samples")
    values, labels, blank = array("d"), [], None
    for index, row in enumerate(reader, start=1):
        if not any(c.strip() for c in row):
            blank = index if blank is None else blank
            continue
        if blank is not None:   # a blank line between data rows
            raise MeasurementError(source, f"empty, the header has {width} fields", blank)
        if index > allowed:
            check_limit("samples", index, source, "", f"the file's data rows (counted as "
                                                      f"read, stopped at row {index:,})")
        if len(row) != width:
            missing = header[len(row)] if len(row) < width else None
            raise MeasurementError(source, f"{len(row)} fields, the header has {width}" +
                                   (f" (no value for '{missing}')" if missing else ""),
                                   index, missing)
        try:
            parsed = [float(row[0]), *map(float, row[2:])]
        except ValueError:
            raise _bad_cell(row, header, index, source) from None
        if not all(map(math.isfinite, parsed)):
            raise _bad_cell(row, header, index, source)
        values.extend(parsed)
        labels.append(row[1].strip())
    n = len(labels)
    return np.frombuffer(values, float).reshape(n, width - 1), tuple(labels), n


def read_csv(path, latency_s=0.0):
    """Measurements of a CSV file (module doc); ``latency_s`` [s] from the bench file.

    Read as a stream (a UTF-8 byte order mark is accepted): a line is refused past
    MAX_CSV_LINE characters or with a NUL character, the rows past the 'samples' limit when
    the first of them is read, before the rest of the file."""
    path = Path(path)
    if not path.is_file():
        raise MeasurementError(path, missing_file_text(path))
    if path.stat().st_size > MAX_CSV_BYTES:
        raise MeasurementError(path, f"{path.stat().st_size} bytes is larger than "
                                     f"{MAX_CSV_BYTES} bytes")
    try:
        with open(path, newline="", encoding="utf-8-sig") as stream:
            reader = csv.reader(_lines(stream, path))
            first = next(reader, None)
            if first is None:
                raise MeasurementError(path, "the file is empty (expected the header "
                                             f"{','.join(CSV_HEAD)},m1_x,...)")
            n_markers = _check_header(first, path)
            header = [h.strip() for h in first]
            data, labels, n = _data_rows(reader, header, path)
    except UnicodeDecodeError as exc:
        raise MeasurementError(path, f"not a text CSV file (not UTF-8 at byte {exc.start} "
                                     f"of a read block)") from None
    except csv.Error as exc:
        raise MeasurementError(path, f"not a CSV file: {exc}") from None
    if not n:
        raise MeasurementError(path, "no data rows after the header")
    t = data[:, 0].copy()
    rows_index = np.arange(1, n + 1)
    check_time_resolution(t, path, rows_index)
    check_increasing(t, path, rows_index)
    wrench = np.ascontiguousarray(data[:, 1:7])
    markers = np.ascontiguousarray(data[:, 7:]).reshape(n, n_markers, 3)
    loads = LoadStream(t, wrench, str(path), rows_index)
    frames = MarkerStream(t, markers, str(path), rows_index)
    if latency_s == 0.0:
        counts = {"marker_frames": len(t), "load_samples": len(t), "frames": len(t),
                  "unmatched_frames": 0, "dropped_marker_frames": dropouts(t),
                  "dropped_load_samples": dropouts(t)}
        return Measurements(str(path), t, wrench, markers, labels, rows_index, counts)
    out = synchronise(loads, frames, latency_s, labels)
    return Measurements(str(path), out.t, out.wrench, out.markers, out.labels, out.rows,
                        out.counts)


def write_csv(path, t, wrench, markers, labels=None):
    """Write measurements in the CSV format (17 significant digits: read back exactly).

    t (n,) [s], wrench (n, 6) [N, N m], markers (n, N, 3) [m], labels (n,) or None (empty).
    """
    markers = np.asarray(markers, float)
    n, n_markers = markers.shape[:2]
    lines = [",".join((*CSV_HEAD, *marker_columns(n_markers)))]
    wrench = np.asarray(wrench, float)
    flat = markers.reshape(n, -1)
    for i in range(n):
        label = labels[i] if labels is not None else ""
        numbers = ",".join(repr(float(v)) for v in (*wrench[i], *flat[i]))
        lines.append(f"{float(t[i])!r},{label},{numbers}")
    return atomic_write_text(path, "\n".join(lines) + "\n")


def write_measured_csv(path, measurements, labels=False):
    """Write CampaignMeasurements as a measured CSV (test labels only with ``labels``)."""
    return write_csv(path, measurements.t, measurements.wrench, measurements.markers,
                     measurements.tests if labels else None)
