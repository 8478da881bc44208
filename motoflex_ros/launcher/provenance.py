"""What made a run: ``bags/<run>/provenance.json``, written by ``motoflex campaign``.

``{"command": "motoflex campaign ...", "package_version": "0.1.0", "git_commit": "<sha>" | null,
"git_dirty": bool | null, "git_note": "..." | null, "started_utc": "...", "seed": 0,
"noise_override_m": null | float, "sensor_noise_m": {component: sigma [m]}, "protocol": null |
"...", "components": [...], "inputs": {absolute path: SHA-256}, "bag": {"file": name, "sha256":
...}}``: ``bag`` is the MCAP file the run recorded, by hash (a bag put in its place is told);
``inputs`` lists every file the run read (components, protocols, the vehicle, files they name),
each read once by the launcher and held to that hash for the whole run
(:mod:`motoflex_ros.input_pins`). Together with status.json (how it ended) and the bag's
metadata.yaml (its time span and ROS distribution) it is the provenance the report shows
(:mod:`motoflex_ros.report.provenance_section`). A run folder without it (an older run) has no
record of these; the report says so rather than guessing.
"""
import json
import shlex
import subprocess
import time
from pathlib import Path

import motoflex_ros
from motoflex_ros.files import atomic_write_text, read_json
from motoflex_ros.input_pins import sha256_file

__all__ = ["PROVENANCE_FILE", "write_provenance", "read_provenance", "git_state",
           "sensor_noise", "utc_stamp"]

PROVENANCE_FILE = "provenance.json"
PACKAGE_DIR = Path(motoflex_ros.__file__).resolve().parent


def utc_stamp(seconds=None):
    """ISO 8601 UTC time of ``seconds`` since the epoch (default: now), to the second."""
    return time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime(seconds))


def git_state(folder=PACKAGE_DIR):
    """(commit, dirty, note) of the git checkout holding ``folder``; (None, None, why) when it
    is not one (an installed package) or git is missing."""
    def git(*args):
        return subprocess.run(["git", "-C", str(folder), *args], capture_output=True,
                              text=True, timeout=30)
    try:
        head = git("rev-parse", "HEAD")
    except (OSError, subprocess.TimeoutExpired) as exc:
        return None, None, f"git not available ({exc})"
    if head.returncode != 0:
        return None, None, f"{folder} is not in a git checkout (an installed package)"
    status = git("status", "--porcelain", "--untracked-files=no")
    return head.stdout.strip(), bool(status.stdout.strip()), None


def sensor_noise(components, protocol=None, noise_override=None):
    """{component: sensor noise standard deviation [m]} the campaign used: the override, else
    each component's protocol's (``protocol`` or its shipped one)."""
    from motoflex_ros.bench.protocols import load_protocol, protocol_for
    if noise_override is not None:
        return {c: float(noise_override) for c in components}
    return {c: float((load_protocol(protocol) if protocol else protocol_for(c)).sensor.noise_m)
            for c in components}


def write_provenance(folder, argv, components, seed, noise_override=None, protocol=None,
                     started=None, inputs=None, bag_file=None):
    """Write ``folder``/provenance.json (atomically) for a campaign run; returns its path.

    ``argv``: the arguments after ``motoflex``; ``started``: the run's start [s since epoch];
    ``inputs``: {absolute path: SHA-256} of the run's input files; ``bag_file``: the MCAP
    file the run recorded.
    """
    commit, dirty, note = git_state()
    record = {"command": shlex.join(["motoflex", *argv]),
              "package_version": motoflex_ros.__version__,
              "git_commit": commit, "git_dirty": dirty, "git_note": note,
              "started_utc": utc_stamp(started), "seed": int(seed),
              "noise_override_m": None if noise_override is None else float(noise_override),
              "sensor_noise_m": sensor_noise(components, protocol, noise_override),
              "protocol": protocol, "components": list(components),
              "inputs": dict(sorted((inputs or {}).items())),
              "bag": None if bag_file is None else {"file": Path(bag_file).name,
                                                    "sha256": sha256_file(bag_file)}}
    return atomic_write_text(Path(folder) / PROVENANCE_FILE, json.dumps(record, indent=1) + "\n")


def read_provenance(folder):
    """The provenance dict of ``folder``; None without the file; {"unreadable": why} if it
    cannot be read."""
    path = Path(folder) / PROVENANCE_FILE
    if not path.is_file():
        return None
    try:
        record = read_json(path)
    except (OSError, ValueError) as exc:
        return {"unreadable": f"{PROVENANCE_FILE}: {exc}"}
    return record if isinstance(record, dict) else {"unreadable": f"{PROVENANCE_FILE}: no dict"}
