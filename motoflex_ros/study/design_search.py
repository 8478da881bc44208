"""The search of ``motoflex study design``: least mass under the stability floors, and the front.

Beyond the paper (issue 26). Two searches on the same evaluations
(:class:`~motoflex_ros.study.design_evaluate.DesignEvaluator`, batched; on Dask with a
scheduler, as the sensitivity study, :func:`motoflex_ros.study.runner.run_study`):

- single objective, scipy's SLSQP: least structural mass subject to every constraint margin >= 0
  (the four stability indices of eq. 15 at least their floors, the first clamped frequency
  and k at least theirs). Why SLSQP: the mass is smooth and cheap with an exact-to-rounding
  gradient, the constraints are few (at most 4 + 2 per component), smooth almost everywhere
  and expensive (0.2 s each); SLSQP needs one constraint Jacobian per iteration, which is a
  batch of n + 1 independent evaluations (forward differences) that runs in parallel on Dask,
  and it handles bounds and inequality constraints directly. A derivative-free method
  (COBYLA/COBYQA) evaluates one design at a time and cannot use the cluster.
- two objectives, pymoo's NSGA-II: structural mass against the smallest stability margin
  min_i (s_i - floor_i), with the frequency and k floors as constraints. A population is one
  batch. Reproducible with a seed (pymoo's and numpy's generator).

Variables are scaled to z in [0, 1] inside their bounds.
"""
from dataclasses import dataclass, field

import numpy as np
import scipy.optimize

from motoflex_ros.errors import ConfigError
from motoflex_ros.study.design_evaluate import DesignBatch
from motoflex_ros.study.design_space import design_configs, members_mass
from motoflex_ros.study.runner import run_study
from motoflex_ros.study.stability_index import INDEX_NAMES

__all__ = ["DesignProblem", "index_floors", "least_mass", "pareto_front", "SLACK"]

SLACK = 1e-4
"""Margin [units of the constraint] the single-objective search keeps from every floor, so
that its optimum meets the floors strictly (finite-difference and continuation rounding)."""
_FD_STEP = 1e-3


def index_floors(space, nominal):
    """{index: floor} with 'nominal' replaced by the nominal design's index ``nominal`` (dict);
    ConfigError naming the file and key when the nominal design is below a given floor."""
    floors = {}
    for name, value in space.index_floors.items():
        floors[name] = float(nominal[name]) if value == "nominal" else float(value)
        if nominal[name] < floors[name]:
            raise ConfigError(space.source, f"constraints.{name}",
                              f"the nominal design does not meet it: {name} = "
                              f"{float(nominal[name]):.4f} < {floors[name]:.4f} (infeasible)")
    return floors


@dataclass(eq=False)
class DesignProblem:
    """Evaluations of a design space with an archive.

    evaluator: the DesignEvaluator; scheduler: None or what run_study takes (an address, a
    Client); floors: {index: floor} (:func:`index_floors`); archive: every evaluation as
    (x [m], outputs dict).
    """

    evaluator: object
    scheduler: object = None
    floors: dict = None
    archive: list = field(default_factory=list)
    workers: int = 1

    @property
    def space(self):
        """The DesignSpace."""
        return self.evaluator.space

    def x_of(self, z):
        """Variables [m] of scaled z (..., variables) in [0, 1]."""
        return self.space.lower + np.clip(z, 0.0, 1.0) * (self.space.upper - self.space.lower)

    def evaluate(self, X):
        """Outputs {name: (runs,)} of the designs X (runs, variables) [m]."""
        X = np.atleast_2d(np.asarray(X, float))
        block = max(1, int(np.ceil(len(X) / (2 * self.workers)))) if self.scheduler else len(X)
        run = run_study(self.evaluator, DesignBatch(self.space.names, X), self.scheduler,
                        progress=False, block_size=block)
        out = run.outputs
        for i, x in enumerate(X):
            self.archive.append((x.copy(), {k: float(v[i]) for k, v in out.items()}))
        return out

    def margins(self, out):
        """(runs, constraints) margins, feasible where all >= 0: index - floor (eq. 15
        units), then f1 / floor - 1 and k / floor - 1 per component."""
        cols = [np.asarray(out[name]) - self.floors[name] for name in self.floors]
        for component, floors in self.space.floors.items():
            if "min_first_frequency_hz" in floors:
                cols.append(np.asarray(out[f"f1_hz_{component}"])
                            / floors["min_first_frequency_hz"] - 1.0)
            if "min_static_k" in floors:
                cols.append(np.asarray(out[f"k_static_{component}"]) / floors["min_static_k"]
                            - 1.0)
        return np.column_stack(cols) if cols else np.zeros((len(out["mass_kg"]), 0))

    @property
    def n_strength(self):
        """Number of strength stand-in constraints (frequency and k floors)."""
        return sum(len(floors) for floors in self.space.floors.values())

    def stability_margin(self, out):
        """Smallest index margin min_i (s_i - floor_i) over the constrained indices (runs,)."""
        names = [n for n in INDEX_NAMES if n in self.floors]
        return np.min(np.column_stack([np.asarray(out[n]) - self.floors[n] for n in names]),
                      axis=1)

    def mass(self, x):
        """Structural mass of the design x [m] [kg] (cheap: no evaluation)."""
        configs = design_configs(self.space, x)
        return self.evaluator.held_mass_kg + sum(members_mass(c) for c in configs.values())


def least_mass(problem, maxiter=40):
    """SLSQP from the nominal design (module docstring): (x [m], scipy OptimizeResult)."""
    span = problem.space.upper - problem.space.lower
    z0 = (problem.space.nominal - problem.space.lower) / span
    cache = {}

    def constraints(z):
        key = tuple(np.round(z, 15))
        if key not in cache:
            cache[key] = problem.margins(problem.evaluate(problem.x_of(z)[None]))[0]
        return cache[key] - SLACK

    def jacobian(z):
        steps = np.where(z + _FD_STEP <= 1.0, _FD_STEP, -_FD_STEP)
        Z = z[None, :] + np.diag(steps)
        shifted = problem.margins(problem.evaluate(problem.x_of(Z)))
        return ((shifted - SLACK) - constraints(z)[None, :]).T / steps[None, :]

    def mass(z):
        return problem.mass(problem.x_of(z))

    def mass_gradient(z):
        base, h = mass(z), 1e-7
        return np.array([(mass(z + h * e) - base) / h for e in np.eye(len(z))])

    result = scipy.optimize.minimize(
        mass, z0, jac=mass_gradient, method="SLSQP", bounds=[(0.0, 1.0)] * len(z0),
        constraints=[{"type": "ineq", "fun": constraints, "jac": jacobian}],
        options={"maxiter": maxiter, "ftol": 1e-6})
    return problem.x_of(result.x), result


def pareto_front(problem, seed, pop_size=24, n_gen=10, extra=()):
    """NSGA-II (pymoo) on (mass, -smallest stability margin) with the frequency and k floors
    as constraints: (X (points, variables) [m], pymoo Result) of the non-dominated feasible
    designs, sorted by mass. The first population is uniform random (numpy generator of
    ``seed``) with the designs ``extra`` ([m], e.g. the nominal and the least-mass design) in
    its first rows."""
    from pymoo.algorithms.moo.nsga2 import NSGA2
    from pymoo.core.problem import Problem
    from pymoo.optimize import minimize

    n_index = len(problem.floors)
    n_other = problem.n_strength

    class _Front(Problem):
        def __init__(self):
            super().__init__(n_var=len(problem.space.names), n_obj=2, n_ieq_constr=n_other,
                             xl=0.0, xu=1.0)

        def _evaluate(self, Z, out, *args, **kwargs):
            outputs = problem.evaluate(problem.x_of(Z))
            out["F"] = np.column_stack([outputs["mass_kg"], -problem.stability_margin(outputs)])
            if n_other:
                out["G"] = -problem.margins(outputs)[:, n_index:]

    span = problem.space.upper - problem.space.lower
    first = np.random.default_rng(int(seed)).random((pop_size, len(span)))
    for i, x in enumerate(list(extra)[:pop_size]):
        first[i] = np.clip((np.asarray(x, float) - problem.space.lower) / span, 0.0, 1.0)
    result = minimize(_Front(), NSGA2(pop_size=pop_size, sampling=first), ("n_gen", n_gen),
                      seed=int(seed), verbose=False)
    Z = np.atleast_2d(result.X)
    order = np.argsort(np.atleast_2d(result.F)[:, 0])
    return problem.x_of(Z[order]), result

