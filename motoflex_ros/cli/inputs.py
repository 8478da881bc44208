"""Inputs shared by several verbs: identification results (from a file or a fresh bench run)
and the components placed in the motorcycle."""
import sys
from pathlib import Path

import numpy as np

from motoflex_ros.config import MOTORCYCLE_COMPONENTS
from motoflex_ros.errors import ConfigError
from motoflex_ros.limits import check_limit
from motoflex_ros.units import kmh_to_ms

__all__ = ["COMPONENTS", "identification_results", "motorcycle_components",
           "add_study_inputs", "add_use_option", "component_roles", "study_speeds",
           "noise_argument", "seed_argument"]

COMPONENTS = MOTORCYCLE_COMPONENTS
_USE = "command line"


def identification_results(path=None, components=None, seed=0, vehicle="touring"):
    """{component: results} from a YAML/JSON file of ``motoflex identify --out``, or, without a
    file, from running the offline bench campaign (seeded) for ``components`` (structures
    Components; None: the shipped motorcycle components), the principal hinges in the metric of
    what ``vehicle``'s bodies hang from each loaded end."""
    if path:
        from motoflex_ros.formats.json_yaml import load_results_file
        return load_results_file(Path(path))
    from motoflex_ros.bench.offline_campaign import identify_components
    from motoflex_ros.cli.output import progress_bar
    from motoflex_ros.formats.component_file import load_components
    from motoflex_ros.study.identified_variants import carried_inertias
    print("running the bench identification ...", file=sys.stderr)
    if components is None:
        components = load_components(COMPONENTS)
    carried = carried_inertias(components, vehicle)
    with progress_bar(len(components), "bench identification", "component") as bar:
        runs = identify_components(components, seed=seed,
                                   progress=lambda _name: bar.update(1), carried=carried)
    return {name: run.identification.to_dict() for name, (_, run) in runs.items()}


def motorcycle_components(names=COMPONENTS, roles=None):
    """{name: structures Component} of the motorcycle components: the shipped ones, or the file
    ``roles[name]`` where one is given (``--use``, :func:`component_roles`; said on stderr)."""
    from motoflex_ros.formats.component_file import load_component

    for name, path in (roles or {}).items():
        if name in names:
            print(f"the {name} is {path} (--use), not the shipped one", file=sys.stderr)
    return {name: load_component((roles or {}).get(name, name)) for name in names}


def add_use_option(parser):
    """``--use FILE`` (repeatable): the engineer's own component in the motorcycle."""
    parser.add_argument("--use", action="append", metavar="FILE",
                        help="a component file (beam, mesh or superelement) that takes the role "
                             "its name gives it in the motorcycle (frame, front_assembly or "
                             "swingarm) instead of the shipped one; repeatable")


def component_roles(files):
    """{role: path} of ``--use FILE ...``: each file's component name (``component`` of a beam
    file, ``name`` or the file's stem of a mesh or superelement file) must be one of the
    motorcycle's components, each at most once. ConfigError naming the file otherwise."""
    from motoflex_ros.formats.component_file import component_name

    roles = {}
    for text in files or ():
        path = Path(text)
        if not path.is_file():
            raise ConfigError(_USE, "--use", f"'{text}' is not a file (give a component YAML; "
                                             "the shipped components are used by default)")
        role = component_name(str(path))
        if role not in COMPONENTS:
            raise ConfigError(str(path), "name", f"component '{role}' takes no role in the "
                                                 f"motorcycle (allowed: {', '.join(COMPONENTS)}; "
                                                 "set `name:` of a mesh or superelement file)")
        if role in roles:
            raise ConfigError(_USE, "--use", f"two files for the {role}: '{roles[role]}' and "
                                             f"'{text}'")
        roles[role] = str(path)
    return roles



def add_study_inputs(parser):
    """The options every study shares: --identified FILE and --vehicle."""
    parser.add_argument("--identified", metavar="FILE",
                        help="identification results (YAML/JSON of motoflex identify --out)")
    parser.add_argument("--vehicle", default="touring", help="vehicle YAML or shipped name")
    add_use_option(parser)


def study_speeds(step_kmh, max_step_kmh):
    """The paper's speed grid [m/s]: 40 to 210 km/h in steps of ``step_kmh``, 210 included."""
    if not 0 < step_kmh <= max_step_kmh:
        raise ConfigError("command line", "--step-kmh",
                          f"must be in (0, {max_step_kmh:g}] km/h, got {step_kmh:g}")
    count = int(np.floor(170.0 / step_kmh + 1e-9)) + 1
    check_limit("speeds", count, "command line", "--step-kmh",
                f"40 to 210 km/h in steps of {step_kmh:g} km/h")
    kmh = 40.0 + step_kmh * np.arange(count)
    if kmh[-1] < 210.0 - 1e-9:
        kmh = np.append(kmh, 210.0)
    return kmh_to_ms(kmh)


def noise_argument(text):
    """Type of --noise for argparse: a sensor-noise standard deviation [m] in [0, 1e-3]."""
    import argparse

    from motoflex_ros.bench.offline_campaign import checked_noise
    try:
        return checked_noise(float(text), "command line", "--noise")
    except ValueError as exc:  # ConfigError is a ValueError; so is float('abc')
        raise argparse.ArgumentTypeError(getattr(exc, "problem", str(exc))) from None


def namespace_argument(text):
    """Type of --namespace for argparse: a ROS namespace ('/rig_a', 'lab/rig_a'), returned
    with its leading '/'; names of letters, digits and '_', not starting with a digit."""
    import argparse
    import re
    name = "/" + text.strip().strip("/")
    if not re.fullmatch(r"(/[A-Za-z_][A-Za-z0-9_]*)+", name):
        raise argparse.ArgumentTypeError(
            f"{text!r} is no ROS namespace: expected names of letters, digits and '_' that do "
            "not start with a digit, separated by '/' (e.g. /rig_a)")
    return name


def seed_argument(text):
    """Type of --seed for argparse: a seed of the sensor noise, a whole number >= 0."""
    import argparse

    from motoflex_ros.bench.offline_campaign import checked_seed
    try:
        value = int(text)
    except ValueError:
        value = text
    try:
        return checked_seed(value, "command line", "--seed")
    except ConfigError as exc:
        raise argparse.ArgumentTypeError(exc.problem) from None
