"""Read a saved rerun recording back: rows per entity path, scalar values, CLI verification.

Used by tests and by ``motoflex rerun`` to check what it wrote. rerun-sdk 0.41 has no
``rerun.dataframe``; the recording is read with ``rerun.chunk.RrdReader``.
"""
import shutil
import subprocess
from collections import Counter
from pathlib import Path

from rerun.chunk import RrdReader

__all__ = ["entity_rows", "scalar_values", "component_rows", "verify_text", "rerun_executable",
           "recordings"]


def recordings(rrd_path):
    """Store entries (kind, application id, recording id) of the recordings in the file."""
    return RrdReader(Path(rrd_path)).recordings()


def entity_rows(rrd_path, static=False):
    """Rows per entity path, {path: rows}: time-stamped rows, or static ones (``static``)."""
    rows = Counter()
    for chunk in RrdReader(Path(rrd_path)).stream().to_chunks():
        if chunk.is_static == static:
            rows[chunk.entity_path] += chunk.num_rows
    return dict(rows)


def scalar_values(rrd_path, entity_path):
    """The Scalars values logged at ``entity_path`` (first value of each row), in row order."""
    values = []
    for chunk in RrdReader(Path(rrd_path)).stream().to_chunks():
        if chunk.entity_path != entity_path:
            continue
        batch = chunk.to_record_batch()
        index = batch.schema.get_field_index("Scalars:scalars")
        if index < 0:       # e.g. the static SeriesLines styling of the same entity
            continue
        values += [row[0] for row in batch.column(index).to_pylist()]
    return values


def component_rows(rrd_path, entity_path, column, timeline=None):
    """Rows of one component column at ``entity_path``, e.g. 'LineStrips3D:strips'.

    Returns [(time, value)] in file order: ``time`` the row's ``timeline`` value (integer
    nanoseconds for a duration timeline, the sequence number otherwise), None for static rows
    or without ``timeline``; ``value`` the row's component batch as plain lists.
    """
    rows = []
    for chunk in RrdReader(Path(rrd_path)).stream().to_chunks():
        if chunk.entity_path != entity_path:
            continue
        batch = chunk.to_record_batch()
        index = batch.schema.get_field_index(column)
        if index < 0:
            continue
        times = [None] * batch.num_rows
        if timeline is not None and not chunk.is_static:
            where = batch.schema.get_field_index(timeline)
            times = batch.column(where).cast("int64").to_pylist()
        rows += zip(times, batch.column(index).to_pylist())
    return rows


def rerun_executable():
    """Path of the rerun CLI binary shipped in rerun-sdk (else ``rerun`` on PATH).

    The binary itself, not the ``bin/rerun`` Python wrapper: the wrapper runs the binary as a
    child and does not pass SIGTERM on, so stopping the wrapper would orphan the viewer.
    """
    try:
        import rerun_cli
    except ImportError:
        return shutil.which("rerun")
    binary = Path(rerun_cli.__file__).with_name("rerun")
    return str(binary) if binary.exists() else shutil.which("rerun")


def verify_text(rrd_path):
    """Output of ``rerun rrd verify``: exit 0 alone is not enough (0 files also exit 0)."""
    result = subprocess.run([rerun_executable(), "rrd", "verify", str(rrd_path)],
                            capture_output=True, text=True, timeout=120)
    return f"exit {result.returncode}\n{result.stdout}{result.stderr}"
