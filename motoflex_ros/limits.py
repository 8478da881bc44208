"""Limits on the work one input may ask for, checked before the work starts.

A configuration value can be valid on its own and still ask for hours of computing or more
memory than the machine has (a mesh of 1e-7 m elements, a free decay of 1e9 periods, 1e11
speeds). Each kind of work is sized first (DOFs of a model, samples and simulated time of a
bench campaign, speeds of a sweep) and refused past its limit with a ConfigError naming the
file, the key, the size asked for and the limit. A limit is raised, for one command, with
``--limit NAME=VALUE`` (every ``motoflex`` verb) or with the environment variable
``MOTOFLEX_LIMIT_<NAME>`` (which node processes inherit).
"""
import math
import os
from dataclasses import dataclass

from motoflex_ros.errors import ConfigError

__all__ = ["Limit", "LIMITS", "limit", "check_limit", "set_limit", "parse_limit", "amount"]


@dataclass(frozen=True)
class Limit:
    """One limit: name (as in --limit NAME=VALUE), default value, unit and what it bounds."""

    name: str
    default: float
    unit: str
    what: str

    @property
    def variable(self):
        """The environment variable that overrides the default."""
        return f"MOTOFLEX_LIMIT_{self.name.upper()}"


LIMITS = {lim.name: lim for lim in (
    # the shipped components have 126-522 DOFs; 60,000 DOFs (a 10,000-element tube) take about
    # 4 s and 250 MB for `motoflex components`
    Limit("dofs", 100_000, "DOFs", "degrees of freedom of one component model"),
    # a solid mesh (component: mesh): 3 DOFs per node; 1e6 DOFs reduce in minutes and take
    # gigabytes (README, benchmarks/bench_mesh.py)
    Limit("mesh_dofs", 1_200_000, "DOFs", "degrees of freedom of one solid mesh component"),
    # the shipped campaigns have 6,500-8,400 samples per component (about 0.3 ms each offline,
    # so about a minute at the limit)
    Limit("samples", 250_000, "samples", "samples of one component's bench campaign"),
    # the shipped campaigns simulate 53-85 s per component
    Limit("simulated_s", 900.0, "s", "simulated time of one component's bench campaign"),
    # a speed sweep: one eigenvalue problem per speed
    Limit("speeds", 10_000, "speeds", "speeds of one eigenvalue sweep"),
)}


def limit(name):
    """The current value of limit ``name`` (its environment variable, else the default)."""
    lim = LIMITS[name]
    text = os.environ.get(lim.variable)
    if not text:
        return lim.default
    try:
        return _positive(text)
    except ValueError:
        raise ConfigError(f"environment variable {lim.variable}", "",
                          f"'{text}' is not a number > 0") from None


def _positive(text):
    value = float(text)
    if not (math.isfinite(value) and value > 0):
        raise ValueError(text)
    return value


def parse_limit(text):
    """(name, value) of a ``NAME=VALUE`` option; ValueError with the allowed names."""
    name, sep, value = text.partition("=")
    if not sep or name not in LIMITS:
        raise ValueError(f"expected NAME=VALUE with NAME one of {', '.join(LIMITS)}, "
                         f"got '{text}'")
    try:
        return name, _positive(value)
    except ValueError:
        raise ValueError(f"{name}: '{value}' is not a number > 0") from None


def set_limit(name, value):
    """Raise (or lower) limit ``name`` for this process and the processes it starts."""
    os.environ[LIMITS[name].variable] = repr(float(value))


def check_limit(name, size, source, key, what=""):
    """ConfigError(source, key) when ``size`` is above limit ``name``; returns ``size``.

    ``what``: how the size came about (e.g. 'the mesh of max_element_length 1e-07 m'), put at
    the start of the message.
    """
    lim, allowed = LIMITS[name], limit(name)
    if not size <= allowed:   # also catches NaN
        start = f"{what} needs" if what else "needs"
        raise ConfigError(source, key, f"{start} {amount(size)} {lim.unit}, above the limit "
                                       f"of {amount(allowed)} {lim.unit} ({lim.what}); raise "
                                       f"it with --limit {name}=N or {lim.variable}=N if you "
                                       f"mean it")
    return size


def amount(value):
    """A count as 10,001; other numbers with 4 significant digits."""
    value = float(value)
    if value.is_integer() and abs(value) < 1e15:
        return f"{int(value):,}"
    return f"{value:.4g}"
