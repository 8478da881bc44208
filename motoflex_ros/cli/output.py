"""Shared output helpers of the CLI verbs: JSON to stdout, tables, atomic file writes."""
import sys
from pathlib import Path

from motoflex_ros.errors import ConfigError
from motoflex_ros.files import OutputError, check_output_path
from motoflex_ros.formats.json_yaml import json_text

__all__ = ["emit_json", "print_table", "add_force_option", "check_new_file", "progress_bar"]


def add_force_option(parser):
    """--force: allow the verb's output file to replace an existing one."""
    parser.add_argument("--force", action="store_true",
                        help="replace the output file if it exists (default: refuse)")


def check_new_file(path, force, option="--out"):
    """ConfigError naming ``option`` when ``path`` exists (and ``force`` is false); an
    OutputError when it is not a regular file (a device, FIFO, socket or directory: refused
    even with ``force``) or its folder is a file. Checked before any work: nothing is
    overwritten silently, and nothing but a regular file ever is."""
    path = Path(path)
    if path.is_dir():
        raise ConfigError("command line", option, f"{path} is a directory; give a file name")
    try:
        check_output_path(path)
    except OutputError as exc:
        raise ConfigError("command line", option, str(exc)) from None
    if path.exists() and not force:
        raise ConfigError("command line", option, f"{path} exists; give --force to replace "
                                                  f"it, or another file name")
    return path


def emit_json(obj, stream=None):
    """Print ``obj`` as JSON on stdout (the machine-readable output of ``--json``)."""
    (stream or sys.stdout).write(json_text(obj))


def print_table(header, rows, stream=None):
    """Print a plain text table with columns padded to their widest cell."""
    stream = stream or sys.stdout
    cells = [list(map(str, header))] + [[str(c) for c in row] for row in rows]
    widths = [max(len(r[i]) for r in cells) for i in range(len(header))]
    for i, row in enumerate(cells):
        stream.write("  ".join(c.rjust(w) if j else c.ljust(w)
                               for j, (c, w) in enumerate(zip(row, widths))) + "\n")
        if i == 0:
            stream.write("  ".join("-" * w for w in widths) + "\n")


def progress_bar(total, desc, unit):
    """The verbs' progress bar on stderr (stdout keeps the table or the JSON alone, so it
    shows with --json too): live on a terminal, a line per 10 % in a log
    (:mod:`motoflex_ros.progress`)."""
    from motoflex_ros.progress import progress_bar as bar
    return bar(total=total, desc=desc, unit=unit)
