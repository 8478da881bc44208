"""Results as a file: JSON, or YAML for a .yaml/.yml path, written atomically.

One writer for ``motoflex identify --out`` and the identification node's ``result_file``, so
their files are equal. Values become plain JSON values first (:func:`to_jsonable`), which the
CLI's ``--json`` output uses too.
"""
import json
import math
from pathlib import Path

import numpy as np
import yaml

from motoflex_ros.files import atomic_write_text

__all__ = ["to_jsonable", "json_text", "write_results"]


def to_jsonable(obj):
    """Convert numpy scalars/arrays and tuples recursively into JSON-ready Python objects.

    Non-finite floats (NaN: an undefined value such as the interval of a single sample) become
    None, i.e. null: strict JSON has no NaN.
    """
    if isinstance(obj, dict):
        return {str(k): to_jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [to_jsonable(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return to_jsonable(obj.tolist())
    if isinstance(obj, np.generic):
        obj = obj.item()
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    return obj


def json_text(obj):
    """``obj`` as strict JSON text (:func:`to_jsonable`, indent 1, newline-terminated): the
    shape of every ``--json`` output and of the JSON result files."""
    return json.dumps(to_jsonable(obj), indent=1, allow_nan=False) + "\n"


def write_results(path, results):
    """Write results ({component: result dict}) as JSON, or YAML for a .yaml/.yml path,
    atomically; returns the path."""
    path = Path(path)
    if path.suffix in (".yaml", ".yml"):
        text = yaml.safe_dump(to_jsonable(results), sort_keys=False)
    else:
        text = json_text(results)
    return atomic_write_text(path, text)
