"""Accuracy of the lumped stiffness models against the flexible motorcycle, Sect. 5.2, Figs 8-9.

For each case (the flexibility of the frame, the front assembly, the swingarm, or all three) the
flexible motorcycle (Craig-Bampton superelements of the same reduced models the bench measured)
is the ground truth; every lumped variant (state of the art, static, torsion, bending) is swept
over the same speeds, weave and wobble are tracked by mode shape in each model, and eq. (18)
gives e_RMS% of their frequency [Hz] and real part [1/s].

Beyond the paper, "principal": the principal hinges in series identified on the bench from the
static test and two moment tests (:mod:`motoflex_ros.identify.principal`), c = gamma k, the
static model's inertia distribution; and three single hinges as the static model's (c = gamma
k):

- "road_load" and "vehicle_load" (:mod:`motoflex_ros.study.load_variants`): identified by eqs.
  1-8 from a bench test loaded through a lever at the tyre contact point, or by the wrench the
  component carries in the flexible motorcycle's wobble (that component flexible);
- "fitted" (:mod:`motoflex_ros.study.fitted`): per component the hinge fitted to the flexible
  motorcycle with that component flexible, searched from the static, road_load and
  vehicle_load hinges.

For "all" the three components' hinges are those of their own cases, put together unchanged
(fitted and identified in turn, not jointly): a component's hinge is the same whichever others
are flexible.
"""
from dataclasses import dataclass, field

import numpy as np

from motoflex_ros.bench.offline_campaign import setup_campaign
from motoflex_ros.errors import ModelError
from motoflex_ros.study.accuracy import weave_wobble_errors
from motoflex_ros.study.fitted import fit_hinges
from motoflex_ros.study.hinge_fit_result import with_fitted
from motoflex_ros.study.hinge_geometry import hinge_of
from motoflex_ros.study.identified_variants import build_variant
from motoflex_ros.study.load_variants import (
    VEHICLE_LOAD_SPEED,
    road_load_tests,
    vehicle_load_tests,
    with_load_tests,
)
from motoflex_ros.vehicle.linearize import linearize
from motoflex_ros.vehicle.lumped import COMPONENTS
from motoflex_ros.vehicle.mode_names import STUDIED_MODES
from motoflex_ros.vehicle.modes import modal_sweep

__all__ = ["CASES", "ACCURACY_VARIANTS", "PAPER_VARIANTS", "AccuracyResult",
           "accuracy_study", "mode_errors", "flexible_reference", "flexible_motorcycle"]

CASES = COMPONENTS + ("all",)
PAPER_VARIANTS = ("state_of_the_art", "static", "torsion", "bending")
ACCURACY_VARIANTS = PAPER_VARIANTS + ("principal", "fitted", "road_load", "vehicle_load")


@dataclass(frozen=True, eq=False)
class AccuracyResult:
    """speeds [m/s]; errors {case: {variant: {quantity: e_RMS%}}}; curves {case: {model:
    {"weave": complex (speeds,), "wobble": ...}}} with model 'flexible' or a variant [1/s];
    fits {component: HingeFit} of the "fitted" variant; loads {component: {"road_load",
    "vehicle_load": LoadTestResult, "wrench": the ModeWrench of vehicle_load}} (both empty
    without those variants)."""

    speeds: np.ndarray
    errors: dict
    curves: dict
    fits: dict = field(default_factory=dict)
    loads: dict = field(default_factory=dict)

    def to_dict(self):
        """The JSON shape of ``motoflex study accuracy --json`` (values in percent)."""
        return {case: {variant: dict(values) for variant, values in table.items()}
                for case, table in self.errors.items()}


def _weave_wobble(model, speeds):
    return _curves(modal_sweep(linearize(model), speeds))


def _curves(sweep):
    return {mode: np.asarray(sweep.modes[mode]) for mode in STUDIED_MODES}


def flexible_motorcycle(vehicle, components, identified, names, speeds, variant="flexible"):
    """(LinearVehicle, {"weave", "wobble"}: eigenvalues over ``speeds`` [1/s]) of the flexible
    motorcycle with the components ``names`` flexible (the accuracy study's ground truth):
    ``variant`` 'flexible' (one clamped superelement per component) or 'flexible_bodies' (the
    per-body superelements joined by the vehicle's joints)."""
    lin = linearize(build_variant(vehicle, variant, list(names), identified, components))
    return lin, _curves(modal_sweep(lin, speeds))


def flexible_reference(vehicle, components, identified, names, speeds):
    """{"weave", "wobble"}: eigenvalues over ``speeds`` [1/s] of the flexible motorcycle with
    the components ``names`` flexible (the accuracy study's ground truth)."""
    return flexible_motorcycle(vehicle, components, identified, names, speeds)[1]


def mode_errors(lumped, flexible, label):
    """{quantity: e_RMS%} (eq. 18) of weave and wobble frequency and real part.

    ``lumped``, ``flexible``: {"weave": eigenvalues over speed, "wobble": ...} [1/s].
    """
    for mode in STUDIED_MODES:
        if not (np.all(np.isfinite(lumped[mode])) and np.all(np.isfinite(flexible[mode]))):
            raise ModelError(f"{label}: {mode} is not tracked at every speed, so eq. (18) "
                             "cannot be evaluated")
    return {q: float(e) for q, e in weave_wobble_errors(lumped, flexible).items()}


def accuracy_study(vehicle, components, identified, speeds, cases=CASES,
                   variants=ACCURACY_VARIANTS, progress=None,
                   vehicle_load_speed=VEHICLE_LOAD_SPEED, vehicle_load_mode="wobble",
                   ground_truth="flexible"):
    """The accuracy study; ``progress`` (optional) is called once per model swept.

    Parameters
    ----------
    vehicle : VehicleModel
        The rigid motorcycle.
    components : mapping
        {component name: structures Component}.
    identified : mapping
        Identification results of the components (``motoflex identify``).
    speeds : array
        Speeds [m/s] (the paper: 40-210 km/h).
    cases, variants : sequence of str
        Which cases (CASES) and lumped variants (ACCURACY_VARIANTS) to compare.
    progress : callable, optional
        Called with no argument after each model is swept.
    vehicle_load_speed, vehicle_load_mode : float, str
        Speed [m/s] and mode of the flexible motorcycle whose wrench loads the vehicle_load
        test (default the wobble at 100 km/h).
    ground_truth : str
        The flexible motorcycle the lumped ones are measured against: 'flexible' (one clamped
        superelement per component) or 'flexible_bodies' (per-body superelements joined by the
        vehicle's joints). The vehicle_load test takes the wrench from the 'flexible' one (the
        wrench its superelement's loaded end carries).

    """
    errors, curves, flexible_models = {}, {}, {}

    def flexible(names, variant=ground_truth):
        key = (tuple(names), variant)
        if key not in flexible_models:
            flexible_models[key] = flexible_motorcycle(vehicle, components, identified, names,
                                                       speeds, variant)
        return flexible_models[key]

    needed = sorted({n for case in cases for n in (COMPONENTS if case == "all" else [case])},
                    key=COMPONENTS.index)
    if set(variants) & {"static", "fitted"}:     # bad results fail before the long work
        build_variant(vehicle, "static", needed, identified, components)
    loads = {}
    if set(variants) & {"road_load", "vehicle_load", "fitted"}:
        setups = {name: setup_campaign(components[name]) for name in needed}
        road = road_load_tests(vehicle, components, needed, setups)
        carried = vehicle_load_tests({n: flexible([n], "flexible")[0] for n in needed},
                                     components, needed, vehicle_load_speed, vehicle_load_mode,
                                     setups)
        loads = {n: {"road_load": road[n], "vehicle_load": carried[n][0],
                     "wrench": carried[n][1]} for n in needed}
    results = identified
    for name, tests in loads.items():
        results = with_load_tests(results, {name: tests["road_load"]})
        results = with_load_tests(results, {name: tests["vehicle_load"]})
    fits = {}
    for case in cases:
        names = list(COMPONENTS) if case == "all" else [case]
        reference = flexible(names)[1]
        curves[case] = {"flexible": reference}
        errors[case] = {}
        if progress:
            progress()
        for variant in variants:
            case_results = results
            if variant == "fitted":
                for name in names:
                    if name not in fits:
                        starts = {t: {name: hinge_of(loads[name][t].model.values)}
                                  for t in ("road_load", "vehicle_load")}
                        fits[name] = fit_hinges(vehicle, components, identified, [name],
                                                flexible([name])[1], speeds, starts=starts)
                case_results = with_fitted(results, [fits[name] for name in names])
            model = build_variant(vehicle, variant, names, case_results, components)
            curves[case][variant] = _weave_wobble(model, speeds)
            errors[case][variant] = mode_errors(curves[case][variant], reference,
                                                f"{case}/{variant}")
            if progress:
                progress()
    return AccuracyResult(np.asarray(speeds, float), errors, curves, fits, loads)
