"""Designs of experiments over the six lumped stiffnesses (Passigato et al. 2023, Sect. 4.3).

Factors as in the paper's Fig. 10: first letter t/b for torsion/bending, second letter f/a/s
for frame, front assembly, swingarm. A design holds coded levels in [-1, 1]; the physical
stiffness of factor i in run r is ``nominal_i (1 + rel_range coded_ri)`` [N m/rad], so coded
-1/+1 are the -/+ rel_range levels (the paper: +/-10 %) and 0 is the nominal value.

Full factorials (any number of levels, 2 and 3 being the usual ones) are in standard order:
the first factor changes fastest. Sampled designs (Monte-Carlo, Latin hypercube, Sobol
sequence) draw the coded levels uniformly in [-1, 1] with scipy.stats.qmc, or with any sampler
passed in (for instance one from SALib) that returns points in the unit cube.
"""
import itertools
from dataclasses import dataclass

import numpy as np
from scipy.stats import qmc

from motoflex_ros.errors import ConfigError
from motoflex_ros.structures.paper_tables import paper_table2_stiffness

__all__ = ["FACTORS", "FACTOR_DESCRIPTIONS", "PAPER_TABLE2_NOMINAL", "Design", "full_factorial",
           "sampled_design"]

FACTORS = ("k_tf", "k_bf", "k_ta", "k_ba", "k_ts", "k_bs")

FACTOR_DESCRIPTIONS = {
    "k_tf": ("frame", "torsion"),
    "k_bf": ("frame", "bending"),
    "k_ta": ("front_assembly", "torsion"),
    "k_ba": ("front_assembly", "bending"),
    "k_ts": ("swingarm", "torsion"),
    "k_bs": ("swingarm", "bending"),
}

# the paper's Table 2 (k_t, k_b after decomposition, eq. 12) [N m/rad]: a published reference
# point; a study normally starts from the values our own identification gives.
PAPER_TABLE2_NOMINAL = {factor: paper_table2_stiffness()[component][f"k_{axis[0]}"]
                        for factor, (component, axis) in FACTOR_DESCRIPTIONS.items()}

_SOURCE = "study design"


@dataclass(frozen=True, eq=False)
class Design:
    """A set of runs over named factors.

    factors: factor names; nominal: nominal values [N m/rad] (factors,); coded: levels in
    [-1, 1] (runs, factors); rel_range: relative half-range of the variation [-]; kind: how
    the runs were made (e.g. "full_factorial_2", "sobol").
    """

    factors: tuple
    nominal: np.ndarray
    coded: np.ndarray
    rel_range: float
    kind: str

    def __len__(self):
        return self.coded.shape[0]

    @property
    def physical(self):
        """Physical factor values [N m/rad], (runs, factors)."""
        return self.nominal * (1.0 + self.rel_range * self.coded)

    def values(self, start=0, stop=None):
        """Physical values of runs start..stop as {factor: array (runs,)} [N m/rad]."""
        block = self.physical[start:stop]
        return {name: block[:, i].copy() for i, name in enumerate(self.factors)}

    def nominal_values(self):
        """Nominal values as {factor: value} [N m/rad]."""
        return {name: float(v) for name, v in zip(self.factors, self.nominal)}


def _nominal_vector(nominal, factors):
    missing = [name for name in factors if name not in nominal]
    if missing:
        raise ConfigError(_SOURCE, "nominal", f"missing factor(s) {', '.join(missing)}")
    values = np.array([float(nominal[name]) for name in factors])
    bad = [name for name, v in zip(factors, values) if not (np.isfinite(v) and v > 0)]
    if bad:
        raise ConfigError(_SOURCE, f"nominal.{bad[0]}", "must be a positive finite stiffness")
    return values


def _check_range(rel_range):
    if not 0.0 < float(rel_range) < 1.0:
        raise ConfigError(_SOURCE, "range", f"must be in (0, 1), got {rel_range}")
    return float(rel_range)


def _frozen(array):
    array = np.ascontiguousarray(array, dtype=float)
    array.setflags(write=False)
    return array


def full_factorial(nominal, levels=2, rel_range=0.10, factors=FACTORS):
    """Full factorial design, ``levels ** len(factors)`` runs in standard order.

    Parameters
    ----------
    nominal : mapping
        Nominal value of every factor [N m/rad].
    levels : int
        Levels per factor (>= 2), equally spaced coded levels from -1 to +1.
    rel_range : float
        Relative half-range [-]: coded +/-1 is nominal (1 +/- rel_range).
    factors : sequence of str
        Factor names, in column order.

    """
    if int(levels) != levels or levels < 2:
        raise ConfigError(_SOURCE, "levels", f"must be an integer >= 2, got {levels}")
    factors = tuple(factors)
    coded_levels = np.linspace(-1.0, 1.0, int(levels))
    rows = itertools.product(coded_levels, repeat=len(factors))
    coded = np.array(list(rows))[:, ::-1]  # first factor fastest
    return Design(factors=factors, nominal=_frozen(_nominal_vector(nominal, factors)),
                  coded=_frozen(coded), rel_range=_check_range(rel_range),
                  kind=f"full_factorial_{int(levels)}")


def _qmc_unit_samples(method, n_runs, dimension, seed):
    if method == "random":
        return np.random.default_rng(seed).random((n_runs, dimension))
    if method == "lhs":
        return qmc.LatinHypercube(d=dimension, seed=seed).random(n_runs)
    if method == "sobol":
        sampler = qmc.Sobol(d=dimension, scramble=True, seed=seed)
        if n_runs & (n_runs - 1) == 0:
            return sampler.random_base2(int(np.log2(n_runs)))
        return sampler.random(n_runs)
    raise ConfigError(_SOURCE, "method", f"'{method}' is not one of sobol, lhs, random")


def sampled_design(nominal, n_runs, rel_range=0.10, method="sobol", seed=0, sampler=None,
                   factors=FACTORS):
    """Monte-Carlo / quasi-Monte-Carlo design, coded levels uniform in [-1, 1].

    Parameters
    ----------
    nominal, rel_range, factors
        As in :func:`full_factorial`.
    n_runs : int
        Number of runs (a power of two keeps a Sobol sequence balanced).
    method : {"sobol", "lhs", "random"}
        scipy.stats.qmc sampler (scrambled Sobol, Latin hypercube) or plain random.
    seed : int
        Seed of the sampler (same seed, same design).
    sampler : callable, optional
        ``sampler(n_runs, n_factors, seed) -> array (runs, n_factors)`` in the unit cube,
        replacing ``method`` (e.g. a SALib sampler); any number of rows is accepted.

    """
    factors = tuple(factors)
    if int(n_runs) != n_runs or n_runs < 1:
        raise ConfigError(_SOURCE, "runs", f"must be a positive integer, got {n_runs}")
    if sampler is None:
        unit = _qmc_unit_samples(method, int(n_runs), len(factors), seed)
        kind = method
    else:
        unit = np.asarray(sampler(int(n_runs), len(factors), seed), dtype=float)
        kind = getattr(sampler, "__name__", "custom")
    if unit.ndim != 2 or unit.shape[1] != len(factors) or np.any((unit < 0) | (unit > 1)):
        raise ConfigError(_SOURCE, "sampler", "must return (runs, factors) points in [0, 1]")
    return Design(factors=factors, nominal=_frozen(_nominal_vector(nominal, factors)),
                  coded=_frozen(2.0 * unit - 1.0), rel_range=_check_range(rel_range), kind=kind)
