"""What a run folder is: bags/<run>/ holding a recorded bag, a rerun recording or run outputs."""
from pathlib import Path

from motoflex_ros.errors import MotoflexError

__all__ = ["RunFolderError", "run_folder", "RUN_MARKERS"]

# any of these makes a directory a run folder (the bag's metadata, the verbs' JSON outputs)
RUN_MARKERS = ("metadata.yaml", "components.json", "identify.json", "identification.json",
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
    raise RunFolderError(f"{path}: not a run folder (none of metadata.yaml, {path.name}.rrd or "
                         "the verbs' JSON outputs is there)")
