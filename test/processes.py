"""The processes a test left behind, found by what their command line names (Linux /proc)."""
import os
from pathlib import Path


def processes_naming(marker, also=""):
    """Pids (other than this one) whose command line contains ``marker`` (e.g. a test's tmp
    dir) and ``also``."""
    pids = []
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit() and int(entry.name) != os.getpid():
            try:
                cmdline = (entry / "cmdline").read_bytes().replace(b"\0", b" ").decode()
            except OSError:
                continue   # ended meanwhile
            if str(marker) in cmdline and also in cmdline:
                pids.append(int(entry.name))
    return pids
