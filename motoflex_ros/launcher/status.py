"""Whether a run folder holds a finished run: ``bags/<run>/status.json``, written last.

``{"status": "complete" | "failed", "reason": null | "...", "time_utc": "..."}`` is written
atomically once everything else of the run is in place (or once it failed). A recorded run (a
folder with a bag or a status) whose status is not "complete" is incomplete: killed before its
status, still running, or failed. While a run is going its results carry a temporary name
(:func:`staged`) and get their own name only when the graph finished cleanly; a failed run
loses them again, so nothing in its folder looks like a success. ``motoflex report`` and
``motoflex replay`` refuse an incomplete run unless ``--allow-incomplete``.
"""
import json
import signal
import time
from contextlib import contextmanager
from pathlib import Path

from motoflex_ros.errors import MotoflexError
from motoflex_ros.files import OutputError, atomic_write_text, read_json
from motoflex_ros.launcher.interrupts import raise_on_sigterm
from motoflex_ros.record.mcap_bag import METADATA_FILE, check_new_bag_dir

__all__ = ["STATUS_FILE", "IncompleteRun", "write_status", "read_status", "incomplete_reason",
           "require_complete", "staged", "run_status"]

STATUS_FILE = "status.json"
COMPLETE, FAILED = "complete", "failed"


class IncompleteRun(MotoflexError):
    """A run folder whose run did not complete."""


def write_status(folder, status, reason=None):
    """Write ``folder``/status.json atomically; returns its path."""
    stamp = time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())
    text = json.dumps({"status": status, "reason": reason, "time_utc": stamp}, indent=1)
    return atomic_write_text(Path(folder) / STATUS_FILE, text + "\n")


def read_status(folder):
    """The status dict of ``folder``, or None if it has none (unreadable: status 'unreadable')."""
    path = Path(folder) / STATUS_FILE
    if not path.is_file():
        return None
    try:
        status = read_json(path)
    except (OSError, ValueError) as exc:
        return {"status": "unreadable", "reason": f"{STATUS_FILE}: {exc}"}
    return status if isinstance(status, dict) else {"status": "unreadable", "reason": "no dict"}


def incomplete_reason(folder):
    """None if ``folder`` holds a complete run or no recorded run at all (only the verbs' JSON
    outputs); otherwise why it is incomplete, in words."""
    folder = Path(folder)
    status = read_status(folder)
    if status is None:
        recorded = (folder / METADATA_FILE).is_file() or any(folder.glob("*.mcap"))
        return (f"{folder}: the run did not finish (no {STATUS_FILE}: interrupted, killed or "
                "still running)") if recorded else None
    if status.get("status") == COMPLETE:
        return None
    return f"{folder}: the run {status.get('status')} ({status.get('reason') or 'no reason'})"


def require_complete(folder, allow_incomplete=False):
    """None for a complete run; for an incomplete one IncompleteRun, or with
    ``allow_incomplete`` its :func:`incomplete_reason`."""
    reason = incomplete_reason(folder)
    if reason and not allow_incomplete:
        raise IncompleteRun(f"{reason}; its results cannot be trusted. Pass --allow-incomplete "
                            "to use it anyway")
    return reason


def staged(path):
    """The temporary name of result ``path`` until its run completes: hidden, beside it, same
    suffix (which decides the format its writer uses)."""
    path = Path(path)
    return path.with_name(f".{path.stem}.partial{path.suffix}")


def _reason(exc):
    if isinstance(exc, KeyboardInterrupt):
        return f"interrupted by {str(exc) or 'SIGINT'}"
    return str(exc) if isinstance(exc, MotoflexError) else f"{type(exc).__name__}: {exc}"


RESERVE_BYTES = 1 << 16
"""Disk space held beside a running run's folder [bytes]: freed to write its failed status
when the disk filled up."""


def _reserve(folder):
    """A hidden file of RESERVE_BYTES beside ``folder`` (its path), or None if none can be
    made (a full or read-only disk: the run's own writes will say so)."""
    path = folder.parent / f".{folder.name}.status-reserve"
    try:
        folder.parent.mkdir(parents=True, exist_ok=True)
        stream = open(path, "xb")   # noqa: SIM115 (closed below)
    except OSError:
        return None
    try:
        with stream:
            stream.write(bytes(RESERVE_BYTES))
    except OSError:
        path.unlink(missing_ok=True)
        return None
    return path


def _write_failed(folder, reason, reserve):
    """Write status "failed"; on a full disk the reserve is freed first, then tried again."""
    try:
        write_status(folder, FAILED, reason)
    except OutputError:
        if reserve is None:
            raise
        reserve.unlink(missing_ok=True)
        write_status(folder, FAILED, reason)


@contextmanager
def run_status(folder, results=()):
    """Around everything a run writes into ``folder`` (which must not exist or be empty): at
    the end status 'complete'; on any error, SIGINT or SIGTERM status 'failed' with the reason,
    the ``results`` (file names in the folder, final and staged) removed, and the error
    re-raised. Nothing is written if the run left no folder. A full disk still gets its
    'failed' status (space for it is reserved beside the folder while the run goes)."""
    folder = check_new_bag_dir(folder)
    previous = signal.signal(signal.SIGTERM, raise_on_sigterm)
    reserve = _reserve(folder)
    try:
        yield folder
        write_status(folder, COMPLETE)
    except BaseException as exc:
        if folder.is_dir():
            for name in results:
                (folder / name).unlink(missing_ok=True)
                staged(folder / name).unlink(missing_ok=True)
            _write_failed(folder, _reason(exc), reserve)
        raise
    finally:
        signal.signal(signal.SIGTERM, previous)
        if reserve is not None:
            reserve.unlink(missing_ok=True)
