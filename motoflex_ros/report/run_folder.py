"""What a run folder is: bags/<run>/ holding a recorded bag, a rerun recording or run outputs."""
import json
from pathlib import Path

from motoflex_ros.errors import MotoflexError
from motoflex_ros.input_pins import sha256_file
from motoflex_ros.record.mcap_bag import METADATA_FILE, BagError, bag_info

__all__ = ["RunFolderError", "run_folder", "RUN_MARKERS", "RUN_RESULT", "is_recorded_run",
           "run_problems"]

# any of these makes a directory a run folder (the bag's metadata, the verbs' JSON outputs)
RUN_MARKERS = (METADATA_FILE, "components.json", "identify.json", "identification.json",
               "eig.json",
               "accuracy.json", "sensitivity.json", "timings.json")


class RunFolderError(MotoflexError):
    """A path given as a run folder is not one."""


def run_folder(path):
    """``path`` as a run folder (Path), or :class:`RunFolderError` naming what is missing."""
    path = Path(path)
    if not path.is_dir():
        raise RunFolderError(f"{path}: not a run folder (no such directory); expected "
                             "bags/<run> as written by 'motoflex campaign'")
    has_rrd = (path / f"{path.name}.rrd").is_file()
    if has_rrd or any((path / name).is_file() for name in RUN_MARKERS):
        return path
    raise RunFolderError(f"{path}: not a run folder (none of {METADATA_FILE}, {path.name}.rrd or "
                         "the verbs' JSON outputs is there)")


RUN_RESULT = "identification.json"
"""The identification a recorded run wrote itself (its identification node's file)."""


def is_recorded_run(folder):
    """Does ``folder`` hold a recorded run (a bag or a status.json), not only verbs' outputs?"""
    folder = Path(folder)
    return any((folder / name).is_file() for name in (METADATA_FILE, "status.json")) or \
        any(folder.glob("*.mcap"))


def run_problems(folder):
    """What makes a recorded run's files missing or inconsistent, in words ([] when none, and
    for a folder of verbs' outputs only): its identification.json (present, a mapping of
    results, one per component of provenance.json, from the inputs provenance.json pins), its
    bag (readable, holding the identification it published, not salvaged by ``bag repair``)."""
    folder = Path(folder)
    if not is_recorded_run(folder):
        return []
    problems = []
    results = _json_file(folder, RUN_RESULT, problems, "the run recorded no identification.json")
    provenance = _json_file(folder, "provenance.json", problems, "no provenance.json")
    if isinstance(results, dict):
        _check_results(results, provenance, problems)
    problems.extend(_bag_problems(folder, provenance))
    return problems


def _json_file(folder, name, problems, absent):
    path = folder / name
    if not path.is_file():
        problems.append(absent)
        return None
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError, RecursionError) as exc:
        problems.append(f"{name} unreadable ({str(exc).splitlines()[0][:120]})")
        return None
    if not isinstance(data, dict):
        problems.append(f"{name} is not a mapping")
        return None
    return data


def _check_results(results, provenance, problems):
    bad = [str(c) for c, r in results.items() if not isinstance(r, dict) or "static" not in r]
    if not results or bad:
        problems.append(f"{RUN_RESULT} holds no identification result"
                        + (f" for '{bad[0]}'" if bad else ""))
        return
    if not isinstance(provenance, dict):
        return
    components = provenance.get("components")
    if isinstance(components, list) and len(components) != len(results):
        problems.append(f"{RUN_RESULT} has {len(results)} components, provenance.json "
                        f"{len(components)}")
    pinned = provenance.get("inputs")
    for name, result in results.items():
        for path, digest in (result.get("inputs") or {}).items():
            if isinstance(pinned, dict) and pinned.get(path) != digest:
                problems.append(f"{RUN_RESULT}: '{name}' came from {path} with SHA-256 "
                                f"{str(digest)[:16]}..., not the run's input "
                                f"({str(pinned.get(path))[:16]}... in provenance.json)")
                return


def _bag_problems(folder, provenance):
    """The bag's problems: as the run recorded it when provenance.json has its SHA-256 (one
    pass of hashing, about 1 GB/s; any flipped bit shows), else every chunk's CRC read; a
    bag that differs is then read chunk by chunk to say where it is damaged."""
    recorded = (provenance or {}).get("bag")
    recorded = recorded.get("sha256") if isinstance(recorded, dict) else None
    try:
        info = bag_info(folder, verify=recorded is None)
        if recorded is not None and recorded != sha256_file(info.mcap_file):
            bag_info(folder, verify=True)   # a damaged chunk: named by the BagError
            return [f"its bag {info.mcap_file.name} is not the one the run recorded (its "
                    f"SHA-256 differs from provenance.json's)"]
    except BagError as exc:
        return [f"its bag is not readable ({exc})"]
    problems = []
    if info.repaired:
        problems.append(f"its bag was repaired by 'motoflex bag repair' ({info.repaired})")
    if info.count("/identification/results") < 1:
        problems.append("its bag holds no /identification/results")
    return problems
