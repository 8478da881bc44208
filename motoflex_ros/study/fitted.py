"""A lumped hinge fitted to the flexible motorcycle: the "fitted" variant (beyond the paper).

The paper identifies each component's hinge on the bench; here, for comparison, the single
hinge per component that the motorcycle itself asks for: the axis (in the component's symmetry
plane), its position and the stiffness k (c = gamma k, gamma = 0.001 s, as the static models)
that minimise J, the root of the summed squares of the e_RMS% (eq. 18) of weave and wobble
frequency and real part against the flexible motorcycle (the objective, its variables, its
tie-break and the conditioning: :mod:`motoflex_ros.study.hinge_fit_problem`; the hinge itself:
:mod:`motoflex_ros.study.hinge_geometry`; the result: :mod:`motoflex_ros.study.hinge_fit_result`).
The flexible reference is an input (the curves the accuracy study computes from its flexible
motorcycle), so the fit follows that reference however it is built.

Search: Nelder-Mead (scipy) from the static identification and from the best (as it is) of
any other starts given (the accuracy study gives the road_load and vehicle_load hinges: from
static alone the front assembly's search ends in a local minimum), each on about 12 of the
speeds, with one restart; the best end point is polished on all speeds.

With several components in ``names`` the hinges are fitted jointly (one simplex over all their
variables); the accuracy study instead fits each on its own case (in turn).
"""
import time

import numpy as np
import scipy.optimize

from motoflex_ros.errors import ModelError
from motoflex_ros.study.hinge_fit_problem import (
    FAILED_OBJECTIVE,
    STEPS,
    TIE_BREAK,
    HingeFitProblem,
    objective_of,
)
from motoflex_ros.study.hinge_fit_result import HingeFit
from motoflex_ros.study.hinge_geometry import end_compliance, hinge_compliance, hinge_from_line

__all__ = ["fit_hinges", "fit_under_compliance"]


def fit_under_compliance(problem, name, wrench, compliance, betas, arms, xatol=0.05,
                         fatol=0.005):
    """The best hinge of ``name`` whose compliance under ``wrench`` is ``compliance``.

    The fit with the equality w . C_h . w = ``compliance`` [m/N] (the FE model's w . C . w,
    :func:`hinge_compliance`): k follows from the axis and its position, k = (s . w)^2 /
    compliance, and J is minimised over the axis angle and the arm b alone: over the grid
    ``betas`` x ``arms`` [rad, m] (all hinges at once), then by Nelder-Mead from the grid's
    best (steps of 2 deg and 1 cm). The other components keep their static hinges.
    Returns (Hinge, {quantity: e_RMS%}).
    """
    site = problem.sites[name]

    def hinge(beta, b):
        unit = hinge_from_line(site, beta, b, 1.0)
        return hinge_from_line(site, beta, b, hinge_compliance(site, unit, wrench) / compliance)

    def runs(points):
        out = []
        for beta, b in points:
            try:
                out.append({**problem.static, name: hinge(beta, b)})
            except ModelError:                       # an axis along O-q0 has no l
                out.append(None)
        return out

    grid = [(beta, b) for beta in betas for b in arms]
    candidates = runs(grid)
    usable = [i for i, r in enumerate(candidates) if r is not None and r[name].k > 0.0]
    values = problem.objectives([candidates[i] for i in usable])
    start = np.array(grid[usable[int(np.argmin(values))]]) / [STEPS["beta"], STEPS["b"]]

    def objective(x):
        run = runs([x * [STEPS["beta"], STEPS["b"]]])[0]
        if run is None or not run[name].k > 0.0:
            return FAILED_OBJECTIVE
        try:
            return objective_of(problem.errors([run])[0])
        except (ModelError, np.linalg.LinAlgError):
            return FAILED_OBJECTIVE

    best = scipy.optimize.minimize(objective, start, method="Nelder-Mead",
                                   options={"xatol": xatol, "fatol": fatol})
    found = hinge(*(best.x * [STEPS["beta"], STEPS["b"]]))
    return found, problem.errors([{**problem.static, name: found}])[0]


def _coarse_index(n, step):
    """Every ``step``-th speed index, the last one included."""
    index = np.arange(0, n, max(int(step), 1))
    return index if index[-1] == n - 1 else np.append(index, n - 1)

def _simplex_search(problem, x0, first_step, xatol, fatol, limit, restarts):
    """Nelder-Mead from x0 (first simplex edge ``first_step``), restarted from its best point
    with a unit simplex while that improves J by more than fatol."""
    best = None
    for attempt in range(restarts + 1):
        step = first_step if attempt == 0 else 1.0
        simplex = np.vstack([x0, x0 + step * np.eye(len(x0))])
        left = limit - problem.evaluations
        if left <= len(x0) + 1:
            break
        run = scipy.optimize.minimize(problem.objective, x0, method="Nelder-Mead",
                                      options={"initial_simplex": simplex, "xatol": xatol,
                                               "fatol": fatol, "maxfev": left})
        improved = best is None or run.fun < best.fun - fatol
        if best is None or run.fun < best.fun:
            best = run
        if not improved:
            break
        x0 = best.x
    return best


def fit_hinges(vehicle, components, identified, names, reference, speeds, starts=None,
               max_evaluations=None, xatol=0.1, fatol=0.01, restarts=1, first_step=5.0,
               coarse_speeds=12, tie_break=TIE_BREAK):
    """Fit one hinge per component of ``names`` to the flexible reference (module docstring).

    Parameters
    ----------
    vehicle : VehicleModel
        The rigid motorcycle.
    components : mapping
        {component name: structures Component} placed in it.
    identified : mapping
        Identification results (the static hinges the search starts from).
    names : sequence of str
        Components with a fitted hinge; several are fitted jointly.
    reference : mapping
        {"weave", "wobble"}: eigenvalues over ``speeds`` of the flexible motorcycle [1/s].
    speeds : array
        Speeds [m/s] (the paper: 40-210 km/h).
    starts : mapping, optional
        More starting points {label: {component: Hinge}} besides the static identification
        (e.g. the hinges of the road_load and vehicle_load bench tests); the search runs from
        the static one and from the one of these with the lowest J as it is.
    max_evaluations : int, optional
        Objective evaluations allowed per start (default 300 per component).
    xatol, fatol : float
        Nelder-Mead tolerances on the scaled variables and on J [%].
    restarts : int
        Nelder-Mead restarts from the best point (a fresh unit simplex) while they improve J.
    first_step : float
        Edge of the first simplex in scaled variables (5: 10 deg, 5 cm, 50 % of k).
    coarse_speeds : int
        The search from each start runs on about this many of the speeds (every n-th, the
        last included); the best end point is then polished on all speeds.
    tie_break : float
        Weight [% per scaled step] of the distance from the static hinges in the simplex's
        objective (:data:`~motoflex_ros.study.hinge_fit_problem.TIE_BREAK`).

    Returns
    -------
    HingeFit

    """
    clock = time.perf_counter()
    problem = HingeFitProblem(vehicle, components, identified, names, reference, speeds,
                              tie_break)
    limit = max_evaluations or 300 * len(problem.names)
    others = {label: {n: hinges.get(n, problem.static[n]) for n in problem.names}
              for label, hinges in (starts or {}).items()}
    step = max(1, round(len(problem.speeds) / coarse_speeds))
    coarse = problem.on_speeds(_coarse_index(len(problem.speeds), step))
    candidates = {"static": dict(problem.static)}
    if others:       # the other start that fits best as it is (one batched evaluation)
        labels = list(others)
        first = [objective_of(e) for e in coarse.errors([others[k] for k in labels])]
        candidates[labels[int(np.argmin(first))]] = others[labels[int(np.argmin(first))]]
    ends, evaluations = {}, 0
    for label, hinges in candidates.items():
        coarse.evaluations = 0
        ends[label] = _simplex_search(coarse, coarse.variables(hinges), first_step, xatol,
                                      fatol, limit, restarts)
        evaluations += coarse.evaluations
    winner = min(ends, key=lambda label: ends[label].fun)
    best = _simplex_search(problem, ends[winner].x, 1.0, xatol, fatol, limit, restarts)
    problem.evaluations += evaluations
    hinges = problem.hinges(best.x)
    static_errors, errors = problem.errors([problem.static, hinges])
    conditioning = problem.conditioning(hinges)
    try:
        spring = problem.spring_errors({n: np.linalg.inv(end_compliance(components[n]))
                                        for n in problem.names})
    except ModelError:
        spring = None
    searched = {label: {"objective": float(end.fun) - coarse.tie_break(end.x),
                        "hinges": {n: h.to_dict() for n, h in problem.hinges(end.x).items()}}
                for label, end in ends.items()}
    return HingeFit(problem.names, hinges, dict(problem.static), errors, static_errors,
                    objective_of(errors), conditioning, problem.evaluations,
                    time.perf_counter() - clock, "jointly" if len(problem.names) > 1
                    else "single", problem.speeds, winner, searched, spring)
