"""The report's provenance: what the run folder records about how the run was made.

Read from status.json (how the run ended; or the outcome the campaign hands over, since it
writes the report before status.json), the bag's metadata.yaml (its time span, message
count and ROS distribution) and provenance.json (command, package version, git commit, seed,
sensor noise, written by ``motoflex campaign``). A field the run does not record is shown as
"not recorded" with the reason, never filled in; what built the report itself (version,
commit, time) is listed apart, since it may differ from what made the run.
"""
import motoflex_ros
from motoflex_ros.config import load_yaml
from motoflex_ros.errors import ConfigError
from motoflex_ros.launcher.provenance import (
    PROVENANCE_FILE,
    git_state,
    read_provenance,
    utc_stamp,
)
from motoflex_ros.launcher.status import STATUS_FILE, read_status
from motoflex_ros.record.mcap_bag import METADATA_FILE
from motoflex_ros.report.tables import Cell, Table
from motoflex_ros.units import NS_PER_S

__all__ = ["provenance_table", "NOT_RECORDED"]

NOT_RECORDED = "not recorded"


def _metadata(folder):
    """The rosbag2 metadata dict of the bag in ``folder``, or (None, why)."""
    path = folder / METADATA_FILE
    if not path.is_file():
        return None, f"no {METADATA_FILE} (no bag in the run folder)"
    try:
        return load_yaml(path)["rosbag2_bagfile_information"], None
    except (OSError, ConfigError, KeyError, TypeError) as exc:
        return None, f"{METADATA_FILE} unreadable ({exc})"


def _bag_rows(folder):
    info, why = _metadata(folder)
    fields = ("bag start (UTC)", "bag duration [s]", "messages in the bag", "ROS distribution")
    if info is None:
        return [(f, None, why) for f in fields]
    try:
        start_ns = info["starting_time"]["nanoseconds_since_epoch"]
        start = utc_stamp(start_ns / NS_PER_S)
        values = (start, f"{info['duration']['nanoseconds'] / NS_PER_S:.2f}",
                  int(info["message_count"]), _plain(info.get("ros_distro")))
    except (KeyError, TypeError, ValueError, OverflowError, OSError) as exc:
        why = f"{METADATA_FILE} unreadable (no valid {exc})" if isinstance(exc, KeyError) \
            else f"{METADATA_FILE} unreadable ({exc})"
        return [(f, None, why) for f in fields]
    return list(zip(fields, values, [METADATA_FILE] * 4))


def _status_rows(folder, outcome=None):
    status = outcome if outcome is not None else read_status(folder)
    if status is None:
        why = f"no {STATUS_FILE}"
        return [("run status", None, why), ("run ended (UTC)", None, why)]
    state = status.get("status")
    if status.get("reason"):
        state = f"{state} ({status['reason']})"
    source = status.get("source", STATUS_FILE)
    return [("run status", state, source), ("run ended (UTC)", status.get("time_utc"), source)]


def _commit_text(commit, dirty, note):
    if commit is None:
        return None, note
    return commit + (" (with uncommitted changes)" if dirty else ""), None


def _noise_text(noise):
    """'frame 5e-06, ...' of the record's sensor_noise_m, or (None, why) when it is not a
    mapping of numbers (a hand-edited file)."""
    if not noise:
        return None, f"not in {PROVENANCE_FILE}"
    if not isinstance(noise, dict) or not all(
            isinstance(v, (int, float)) and not isinstance(v, bool) for v in noise.values()):
        return None, f"{PROVENANCE_FILE}: key 'sensor_noise_m' is not a mapping of numbers [m]"
    return ", ".join(f"{c} {v:g}" for c, v in noise.items()), None


def _plain(value):
    """A scalar of the record as it is; a list or mapping where a scalar belongs: None."""
    return value if isinstance(value, (str, int, float)) else None


def _run_rows(folder):
    record = read_provenance(folder)
    fields = ("command", "run started (UTC)", "motoflex_ros version", "git commit", "seed",
              "sensor noise [m]")
    if record is None or "unreadable" in record:
        why = (record or {}).get("unreadable", f"no {PROVENANCE_FILE} in the run folder "
                                 "(a run made before motoflex campaign wrote it)")
        return [(f, None, why) for f in fields]
    commit, commit_why = _commit_text(_plain(record.get("git_commit")),
                                      record.get("git_dirty"), _plain(record.get("git_note")))
    noise_text, noise_why = _noise_text(record.get("sensor_noise_m"))
    values = (record.get("command"), record.get("started_utc"), record.get("package_version"),
              commit, record.get("seed"), noise_text)
    missing = {"git commit": commit_why, "sensor noise [m]": noise_why}
    return [(f, _plain(v), PROVENANCE_FILE if _plain(v) is not None else
             (missing.get(f) or f"not in {PROVENANCE_FILE}"))
            for f, v in zip(fields, values)]


def _report_rows():
    commit, why = _commit_text(*git_state())
    return [("report built (UTC)", utc_stamp(), "this report"),
            ("report built by motoflex_ros", motoflex_ros.__version__, "this report"),
            ("report built at git commit", commit, why or "this report")]


def _row(field, value, source):
    if value is None:
        return (Cell(field), Cell(NOT_RECORDED, kind="missing", path=field), Cell(source))
    return (Cell(field), Cell(str(value), kind="provenance", file=source, path=field),
            Cell(source))


def provenance_table(folder, outcome=None):
    """Table 'provenance': field, value ('not recorded' where the run has none) and source.

    ``outcome``: the run's status dict (as status.json holds it, with a ``source``) when the
    caller knows it before status.json is written (the campaign writes the report first)."""
    rows = [*_run_rows(folder), *_status_rows(folder, outcome), *_bag_rows(folder),
            *_report_rows()]
    return Table("provenance", "How this run was made", ("field", "value", "source"),
                 tuple(_row(*r) for r in rows),
                 "From the run folder's provenance.json, status.json and metadata.yaml; "
                 "a value the run does not record is marked 'not recorded', not guessed.")
