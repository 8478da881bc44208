"""Inputs shared by several verbs: identification results (from a file or a fresh bench run)
and the components placed in the motorcycle."""
import sys
from pathlib import Path

from motoflex_ros.config import MOTORCYCLE_COMPONENTS, load_yaml
from motoflex_ros.errors import ConfigError

__all__ = ["COMPONENTS", "identification_results", "motorcycle_components"]

COMPONENTS = MOTORCYCLE_COMPONENTS


def identification_results(path=None, components=COMPONENTS, seed=0):
    """{component: results} from a YAML/JSON file of ``motoflex identify --out``, or, without a
    file, from running the offline bench campaign (seeded) for ``components``."""
    if path:
        data = load_yaml(Path(path))
        if not isinstance(data, dict):
            raise ConfigError(path, "", "expected a mapping {component: results}")
        return data
    from motoflex_ros.bench.campaign import identify_components

    print("running the bench identification ...", file=sys.stderr)
    runs = identify_components(list(components), seed=seed)
    return {name: run.identification.to_dict() for name, (_, run) in runs.items()}


def motorcycle_components(names=COMPONENTS):
    """{name: structures Component} of the shipped motorcycle components."""
    from motoflex_ros.structures.components import load_component

    return {name: load_component(name) for name in names}
