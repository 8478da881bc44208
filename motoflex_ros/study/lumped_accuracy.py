"""Accuracy of the lumped stiffness models against the flexible motorcycle, Sect. 5.2, Figs 8-9.

For each case (the flexibility of the frame, the front assembly, the swingarm, or all three) the
flexible motorcycle (Craig-Bampton superelements of the same reduced models the bench measured)
is the ground truth; every lumped variant (state of the art, static, torsion, bending) is swept
over the same speeds, weave and wobble are tracked by mode shape in each model, and eq. (18)
gives e_RMS% of their frequency [Hz] and real part [1/s].
"""
from dataclasses import dataclass

import numpy as np

from motoflex_ros.errors import ModelError
from motoflex_ros.study.accuracy import rms_error_percent
from motoflex_ros.study.variants import build_variant
from motoflex_ros.vehicle.linearize import linearize
from motoflex_ros.vehicle.lumped import COMPONENTS
from motoflex_ros.vehicle.modes import modal_sweep

__all__ = ["CASES", "ACCURACY_VARIANTS", "QUANTITIES", "AccuracyResult", "accuracy_study",
           "mode_errors"]

CASES = COMPONENTS + ("all",)
ACCURACY_VARIANTS = ("state_of_the_art", "static", "torsion", "bending")
QUANTITIES = ("weave_f", "weave_re", "wobble_f", "wobble_re")


@dataclass(frozen=True, eq=False)
class AccuracyResult:
    """speeds [m/s]; errors {case: {variant: {quantity: e_RMS%}}}; curves {case: {model:
    {"weave": complex (speeds,), "wobble": ...}}} with model 'flexible' or a variant [1/s]."""

    speeds: np.ndarray
    errors: dict
    curves: dict

    def to_dict(self):
        """The JSON shape of ``motoflex study accuracy --json`` (values in percent)."""
        return {case: {variant: dict(values) for variant, values in table.items()}
                for case, table in self.errors.items()}


def _weave_wobble(model, speeds):
    sweep = modal_sweep(linearize(model), speeds)
    return {mode: np.asarray(sweep.modes[mode]) for mode in ("weave", "wobble")}


def mode_errors(lumped, flexible, label):
    """{quantity: e_RMS%} (eq. 18) of weave and wobble frequency and real part.

    ``lumped``, ``flexible``: {"weave": eigenvalues over speed, "wobble": ...} [1/s].
    """
    out = {}
    for mode in ("weave", "wobble"):
        lu, fl = lumped[mode], flexible[mode]
        if not (np.all(np.isfinite(lu)) and np.all(np.isfinite(fl))):
            raise ModelError(f"{label}: {mode} is not tracked at every speed, so eq. (18) "
                             "cannot be evaluated")
        out[f"{mode}_f"] = float(rms_error_percent(lu.imag / (2 * np.pi), fl.imag / (2 * np.pi)))
        out[f"{mode}_re"] = float(rms_error_percent(lu.real, fl.real))
    return out


def accuracy_study(vehicle, components, identified, speeds, cases=CASES,
                   variants=ACCURACY_VARIANTS, progress=None):
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

    """
    errors, curves = {}, {}
    for case in cases:
        names = list(COMPONENTS) if case == "all" else [case]
        flexible = _weave_wobble(build_variant(vehicle, "flexible", names, identified,
                                               components), speeds)
        curves[case] = {"flexible": flexible}
        errors[case] = {}
        if progress:
            progress()
        for variant in variants:
            model = build_variant(vehicle, variant, names, identified, components)
            curves[case][variant] = _weave_wobble(model, speeds)
            errors[case][variant] = mode_errors(curves[case][variant], flexible,
                                                f"{case}/{variant}")
            if progress:
                progress()
    return AccuracyResult(np.asarray(speeds, float), errors, curves)
