"""``motoflex study design`` as one function: nominal, Pareto front, lightest feasible design.

Beyond the paper (issue 26). Runs the single-objective search (least mass under the floors) and
the two-objective front (mass against the smallest stability margin) of
:mod:`motoflex_ros.study.design_search`, then re-evaluates every reported design by the full
engine: the changed components reduced as ``motoflex eig --use`` reduces them (20 modes up to
600 Hz), the flexible motorcycle built and linearized from scratch
(:func:`motoflex_ros.vehicle.linearize.linearize`), weave and wobble named by the engine's
modal sweep and tracked, eqs. (13)-(15). ``full_check`` says the difference.

The stiffness change of a design is given as the change of the modal stiffness omega^2 of each
component's first torsion and first bending mode of the clamped model (the factors k_t, k_b
of the flexible sensitivity study, :mod:`motoflex_ros.study.flexible_sensitivity`), beside
the paper's advice (Sect. 5.3): front assembly torsion moderate, front bending tuned to the
motorcycle, swingarm bending low and torsion high.
"""
import time
from dataclasses import dataclass

import numpy as np

from motoflex_ros.study.design_evaluate import STATIC_FORCE, DesignBatch, StackedPencil
from motoflex_ros.study.design_search import DesignProblem, index_floors, least_mass, pareto_front
from motoflex_ros.study.design_space import component_with, design_configs
from motoflex_ros.study.factorial import FACTOR_DESCRIPTIONS
from motoflex_ros.study.identified_variants import build_variant
from motoflex_ros.study.motorcycle import _mode_targets
from motoflex_ros.study.runner import run_study
from motoflex_ros.study.sensitivity import stability_indices
from motoflex_ros.study.stability_index import INDEX_NAMES
from motoflex_ros.study.tracked import HomotopyStart, TrackedModeStudy
from motoflex_ros.vehicle.linearize import linearize
from motoflex_ros.vehicle.modes import modal_sweep

__all__ = ["DesignPoint", "DesignStudyResult", "FullEvaluator", "run_design_study",
           "stiffness_changes", "PAPER_ADVICE", "FEASIBILITY_TOL"]

FEASIBILITY_TOL = 1e-9
"""A floor counts as met down to this much below it [units of the index]: the nominal design
meets its own floors on the full engine to rounding (differences of 1e-14)."""

PAPER_ADVICE = {
    "k_ta": "moderate (too high destabilises wobble at every speed)",
    "k_ba": "tuned to the whole motorcycle (+ high-speed weave, low-speed wobble; - high-speed "
            "wobble)",
    "k_ts": "high",
    "k_bs": "relatively low (+ high-speed weave)",
    "k_tf": "high (+ high-speed weave, low-speed wobble; slightly - high-speed wobble)",
    "k_bf": "high (+ high-speed weave, low-speed wobble; slightly - high-speed wobble)",
}
"""The paper's advice in words, Sect. 5.3 (Passigato et al. 2023), per factor of Fig. 10."""


@dataclass(frozen=True, eq=False)
class DesignPoint:
    """A reported design: x (variables,) [m]; outputs of the cheap evaluation (mass_kg [kg],
    the four indices of eq. 15 and the strength stand-ins); margins (constraints,);
    full_check: the full engine's indices and the differences (None for the nominal)."""

    x: np.ndarray
    outputs: dict
    margins: np.ndarray
    full_check: dict = None

    @property
    def feasible(self):
        """True when every margin is >= -FEASIBILITY_TOL (on the cheap evaluation)."""
        return bool(np.all(self.margins >= -FEASIBILITY_TOL))


@dataclass(frozen=True, eq=False)
class DesignStudyResult:
    """nominal, pareto (list), lightest (DesignPoint or None), why_none (text when no design
    lighter than the nominal met every constraint), floors {index: floor}, space, seconds
    {stage: wall time [s]}, evaluations (count), stiffness {factor: relative change of the
    lightest design}."""

    nominal: DesignPoint
    pareto: list
    lightest: DesignPoint
    why_none: str
    floors: dict
    space: object
    seconds: dict
    evaluations: int
    stiffness: dict

    def _point(self, point, with_check=True):
        out = {"mass_kg": point.outputs["mass_kg"],
               "indices": {n: point.outputs[n] for n in INDEX_NAMES},
               "variables": dict(zip(self.space.names, map(float, point.x)))}
        if with_check:
            out["full_check"] = point.full_check
        return out

    def to_dict(self, files=None):
        """The JSON of ``motoflex study design --json`` (issue 26); ``files`` {component: path}
        of the lightest feasible design's component files."""
        nominal = self._point(self.nominal, with_check=False)
        del nominal["variables"]
        lightest = None
        if self.lightest is not None:
            lightest = {**self._point(self.lightest), "files": dict(files or {})}
        return {"nominal": nominal, "pareto": [self._point(p) for p in self.pareto],
                "lightest_feasible": lightest, "why_none": self.why_none,
                "floors": dict(self.floors), "stiffness_change": dict(self.stiffness),
                "seconds": dict(self.seconds), "evaluations": self.evaluations}


@dataclass(frozen=True, eq=False)
class FullEvaluator:
    """Study function {variable: array (runs,)} [m] -> the four indices (runs,) by the full
    engine (module docstring), one design at a time; picklable for Dask."""

    space: object
    vehicle: object
    components: dict
    speeds: tuple

    def one(self, x):
        """{index: s} of the design x [m] by a full re-reduction and linearization."""
        configs = design_configs(self.space, x)
        comps = {**self.components, **{c: component_with(cfg, self.space.sources[c])
                                       for c, cfg in configs.items()}}
        model = build_variant(self.vehicle, "flexible", list(comps), {}, comps)
        lin = linearize(model)
        speeds = np.asarray(self.speeds)
        e0, a0 = lin.pencil(speeds[:1])
        start = HomotopyStart(nominal=(e0[0], a0[0]),
                              targets=tuple(_mode_targets(modal_sweep(lin, speeds[:1]))))
        study = TrackedModeStudy(StackedPencil(lin.E_coeffs[None], lin.A_coeffs[None]),
                                 tuple(speeds), start)
        indices = stability_indices(speeds, study({"run": np.zeros(1)}))
        return {n: float(indices[n].s[0]) for n in INDEX_NAMES}

    def __call__(self, values):
        X = np.column_stack([np.asarray(values[n], float) for n in self.space.names])
        rows = [self.one(x) for x in X]
        return {n: np.array([r[n] for r in rows]) for n in INDEX_NAMES}


def stiffness_changes(space, components, x):
    """Relative stiffness changes of the design x [m] against the nominal components.

    {"k_static": {component: k / k_nom - 1} (k about the static deformation axis, eq. 8, from
    a 100 N lateral force), "modal": {factor: omega^2 / omega_nom^2 - 1}} with the factors of
    Fig. 10 (k_tf ... k_bs: first torsion and first bending mode of the clamped model). A
    modal factor is None when the design's first mode of that label is more than twice or
    less than half the nominal's frequency: the labelling (by the loaded end's motion) moved to
    another mode, the change is not that mode's stiffness.
    """
    configs = design_configs(space, x)
    reduced = {c: (components[c].clamped_reduced(),
                   component_with(cfg, space.sources[c]).clamped_reduced())
               for c, cfg in configs.items()}
    k_static = {c: float(new.static_lateral(STATIC_FORCE).k / old.static_lateral(STATIC_FORCE).k
                         - 1.0) for c, (old, new) in reduced.items()}
    modal = {}
    for factor, (component, label) in FACTOR_DESCRIPTIONS.items():
        if component in reduced:
            old, new = reduced[component]
            ratio = new.frequency(label) / old.frequency(label)
            modal[factor] = float(ratio**2 - 1.0) if 0.5 <= ratio <= 2.0 else None
    return {"k_static": k_static, "modal": modal}


def _checked(problem, full, X, points):
    """Full checks of the designs X, batched like the evaluations."""
    run = run_study(full, DesignBatch(problem.space.names, np.atleast_2d(X)), problem.scheduler,
                    progress=False, block_size=max(1, int(np.ceil(len(X) / 2))))
    out = []
    for i, point in enumerate(points):
        values = {n: float(run.outputs[n][i]) for n in INDEX_NAMES}
        diff = {n: values[n] - point.outputs[n] for n in INDEX_NAMES}
        meets = all(values[n] >= problem.floors[n] - FEASIBILITY_TOL for n in problem.floors)
        check = {"indices": values, "difference": diff,
                 "max_abs_difference": float(max(abs(d) for d in diff.values())),
                 "meets_constraints": bool(meets)}
        out.append(DesignPoint(point.x, point.outputs, point.margins, check))
    return out


def _point_of(problem, x, outputs):
    margins = problem.margins({k: np.array([v]) for k, v in outputs.items()})[0]
    return DesignPoint(np.asarray(x, float), outputs, margins)


def _archived(problem, x):
    """The archived outputs of the design nearest to x (the design itself)."""
    gaps = [np.max(np.abs(xa - x)) for xa, _ in problem.archive]
    return problem.archive[int(np.argmin(gaps))][1]


def _spread(points, count):
    """At most ``count`` points evenly spread over the list (sorted by mass)."""
    if len(points) <= count:
        return points
    return [points[i] for i in np.unique(np.linspace(0, len(points) - 1, count).round()
                                          .astype(int))]


def run_design_study(evaluator, full, seed=0, scheduler=None, workers=1, pop_size=24,
                     n_gen=10, maxiter=40, max_points=24):
    """The whole study (module docstring): a DesignStudyResult.

    evaluator: the DesignEvaluator; full: the FullEvaluator of the same space; seed: NSGA-II's;
    scheduler: None or a Dask address / Client (run_study); pop_size, n_gen: NSGA-II's
    population and generations; maxiter: SLSQP's iterations; max_points: reported Pareto
    points (spread over the front).
    """
    clock = {"start": time.perf_counter()}
    problem = DesignProblem(evaluator, scheduler=scheduler, workers=workers)
    space = evaluator.space
    nominal_out = {k: float(v[0]) for k, v in problem.evaluate(space.nominal[None]).items()}
    problem.floors = index_floors(space, nominal_out)
    nominal = _point_of(problem, space.nominal, nominal_out)
    x_best, _ = least_mass(problem, maxiter=maxiter)
    clock["least_mass"] = time.perf_counter()
    X_front, _ = pareto_front(problem, seed, pop_size, n_gen, extra=[space.nominal, x_best])
    clock["pareto"] = time.perf_counter()
    front = _spread([_point_of(problem, x, _archived(problem, x)) for x in X_front], max_points)
    candidates = sorted((_point_of(problem, x, out) for x, out in problem.archive
                         if out["mass_kg"] < nominal_out["mass_kg"]),
                        key=lambda p: p.outputs["mass_kg"])
    candidates = [p for p in candidates if p.feasible][:3]
    front = _checked(problem, full, [p.x for p in front], front)
    lightest, tried = None, []
    for candidate in candidates:       # the lightest first; the next only if it fails
        tried = _checked(problem, full, [candidate.x], [candidate])
        if tried[0].full_check["meets_constraints"]:
            lightest = tried[0]
            break
    why = "" if lightest else _why_none(candidates)
    clock["full_check"] = time.perf_counter()
    stiffness = stiffness_changes(space, full.components, lightest.x) if lightest else {}
    seconds = {"least_mass": clock["least_mass"] - clock["start"],
               "pareto": clock["pareto"] - clock["least_mass"],
               "full_check": clock["full_check"] - clock["pareto"]}
    return DesignStudyResult(nominal, front, lightest, why, problem.floors, space, seconds,
                             len(problem.archive), stiffness)


def _why_none(candidates):
    if not candidates:
        return ("no evaluated design lighter than the nominal met every floor: the nominal is "
                "the lightest feasible design found")
    return ("the lightest designs that met every floor on the cheap evaluation missed one on "
            "the full engine")
