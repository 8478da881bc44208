"""Shared output helpers of the CLI verbs: JSON to stdout, tables, atomic file writes."""
import json
import sys

from motoflex_ros.files import atomic_write_text
from motoflex_ros.results_file import to_jsonable

__all__ = ["emit_json", "to_jsonable", "atomic_write_text", "print_table"]


def emit_json(obj, stream=None):
    """Print ``obj`` as JSON on stdout (the machine-readable output of ``--json``)."""
    stream = stream or sys.stdout
    json.dump(to_jsonable(obj), stream, indent=1, allow_nan=False)
    stream.write("\n")


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
