"""Results as a file: JSON, or YAML for a .yaml/.yml path, written atomically, and read back.

One writer for ``motoflex identify --out`` and the identification node's ``result_file``, so
their files are equal. Values become plain JSON values first (:func:`to_jsonable`), which the
CLI's ``--json`` output uses too. :func:`load_results_file` reads such a file into the core's
:class:`~motoflex_ros.identify.results.ResultsFile` (``--identified``, the vehicle simulator's
``result_file``).
"""
import json
import math
from pathlib import Path

import numpy as np
import yaml

from motoflex_ros.config import load_yaml
from motoflex_ros.errors import ConfigError
from motoflex_ros.files import atomic_write_text
from motoflex_ros.identify.results import ResultsFile

__all__ = ["to_jsonable", "json_text", "write_results", "load_results_file"]


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


def load_results_file(path, components=()):
    """ResultsFile of a YAML/JSON file of ``motoflex identify --out``; ConfigError naming the
    file when it is missing, not YAML/JSON, not a mapping or lacks one of ``components``."""
    data = load_yaml(path)
    if not isinstance(data, dict):
        raise ConfigError(path, "", "expected a mapping {component: results}")
    missing = [name for name in components if name not in data]
    if missing:
        raise ConfigError(path, missing[0], f"missing: no results of component "
                                            f"'{missing[0]}' (the file has "
                                            f"{', '.join(map(str, data)) or 'none'})")
    return ResultsFile(data, path)
