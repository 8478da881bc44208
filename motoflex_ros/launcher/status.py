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
from motoflex_ros.files import atomic_write_text
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
        status = json.loads(path.read_text())
    except (OSError, ValueError) as exc:
        return {"status": "unreadable", "reason": str(exc)}
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


@contextmanager
def run_status(folder, results=()):
    """Around everything a run writes into ``folder`` (which must not exist or be empty): at
    the end status 'complete'; on any error, SIGINT or SIGTERM status 'failed' with the reason,
    the ``results`` (file names in the folder, final and staged) removed, and the error
    re-raised. Nothing is written if the run left no folder."""
    folder = check_new_bag_dir(folder)
    previous = signal.signal(signal.SIGTERM, raise_on_sigterm)
    try:
        yield folder
    except BaseException as exc:
        if folder.is_dir():
            for name in results:
                (folder / name).unlink(missing_ok=True)
                staged(folder / name).unlink(missing_ok=True)
            write_status(folder, FAILED, _reason(exc))
        raise
    finally:
        signal.signal(signal.SIGTERM, previous)
    write_status(folder, COMPLETE)
