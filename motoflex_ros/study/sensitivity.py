"""The sensitivity analysis of Sect. 4.3 / 5.3 from tracked weave and wobble curves.

Given a design and, per run, the weave and wobble eigenvalues over speed, computes the four
stability indices (weave/wobble x low/high speed, eqs. 13-15), the ANOVA main-effect share of
each and the Pearson coefficient of each factor with each index (eqs. 16-17).

Beyond the paper, extra speed ranges (``extra_ranges_kmh``) add indices named
"<mode>_<lo>-<hi>kmh" (:func:`extra_range_name`), e.g. "wobble_40-95kmh": where a mode's real
part rises with speed, eq. 13 over 40-100 km/h takes its value at 100 km/h, and if the +/-10 %
curves of a factor cross near there the index cannot see that factor's low-speed effect; a
range that stops short of the crossing can (docs/beyond-the-paper-checks.md).
"""
from dataclasses import dataclass

import numpy as np

from motoflex_ros.study.anova import anova
from motoflex_ros.study.correlation import pearson_table
from motoflex_ros.study.factorial import full_factorial
from motoflex_ros.study.runner import run_study
from motoflex_ros.study.stability_index import RANGE_NAMES, stability_index
from motoflex_ros.units import kmh_to_ms
from motoflex_ros.vehicle.mode_names import STUDIED_MODES

__all__ = ["SensitivityResult", "stability_indices", "analyse_sensitivity",
           "run_sensitivity", "extra_range_name"]



def extra_range_name(low_kmh, high_kmh):
    """Name of an extra speed range in the index names: "40-95kmh" for 40 to 95 km/h."""
    return f"{low_kmh:g}-{high_kmh:g}kmh"


def stability_indices(speeds, curves, modes=STUDIED_MODES, ranges=RANGE_NAMES,
                      extra_ranges_kmh=()):
    """{"<mode>_<range>": StabilityIndex} from {mode: eigenvalues (runs, speeds)}.

    ``speeds`` [m/s]; the curves may be complex eigenvalues or real parts [1/s].
    ``extra_ranges_kmh``: (low, high) pairs [km/h] inside the grid, indexed as
    "<mode>_<low>-<high>kmh" after the named ranges.
    """
    out = {f"{mode}_{name}": stability_index(speeds, np.real(curves[mode]), name)
           for mode in modes for name in ranges}
    for low, high in extra_ranges_kmh:
        v_range = (float(kmh_to_ms(low)), float(kmh_to_ms(high)))
        out.update({f"{mode}_{extra_range_name(low, high)}":
                    stability_index(speeds, np.real(curves[mode]), v_range) for mode in modes})
    return out


@dataclass(frozen=True, eq=False)
class SensitivityResult:
    """nominal: {factor: value} [N m/rad]; indices: {index: StabilityIndex};
    anova: {index: AnovaResult}; pearson: {index: {factor: rho}}.
    """

    nominal: dict
    indices: dict
    anova: dict
    pearson: dict

    @property
    def anova_main_share(self):
        """Share of each index's variance due to main effects [-]."""
        return {name: result.main_share for name, result in self.anova.items()}

    def to_dict(self):
        """The JSON shape of ``motoflex study sensitivity --json`` (issue 7); NaN (an index
        that does not vary) becomes None."""
        return {"nominal": dict(self.nominal),
                "indices": {name: index.s.tolist() for name, index in self.indices.items()},
                "anova_main_share": {k: _finite_or_none(v)
                                     for k, v in self.anova_main_share.items()},
                "pearson": {index: {f: _finite_or_none(rho) for f, rho in row.items()}
                            for index, row in self.pearson.items()}}


def _finite_or_none(value):
    return float(value) if np.isfinite(value) else None


def analyse_sensitivity(design, speeds, curves, extra_ranges_kmh=()):
    """Indices, ANOVA (main effects + two-factor interactions) and Pearson for a design.

    ``design`` is a factorial Design; ``curves`` maps "weave" and "wobble" to eigenvalues
    (runs, speeds) [1/s] on ``speeds`` [m/s], runs in design order; ``extra_ranges_kmh`` as in
    :func:`stability_indices`.
    """
    indices = stability_indices(speeds, curves, extra_ranges_kmh=extra_ranges_kmh)
    responses = {name: index.s for name, index in indices.items()}
    return SensitivityResult(
        nominal=design.nominal_values(), indices=indices,
        anova={name: anova(design.coded, s, design.factors) for name, s in responses.items()},
        pearson=pearson_table(design, responses))


def run_sensitivity(study_function, nominal, speeds, levels=2, rel_range=0.10, scheduler=None,
                    progress=True, extra_ranges_kmh=()):
    """The whole sensitivity study: full factorial, study runs, indices, ANOVA, Pearson.

    ``study_function`` maps {factor: array (runs,)} [N m/rad] to {"weave": ..., "wobble": ...}
    eigenvalues (runs, speeds) on ``speeds`` [m/s] (e.g. from
    :func:`motoflex_ros.study.tracked.pencil_study`); the factors are ``nominal``'s keys in its
    order (the paper's six, or the principal hinges'); ``scheduler`` as in
    :func:`motoflex_ros.study.runner.run_study`; ``extra_ranges_kmh`` as in
    :func:`stability_indices`. Returns (SensitivityResult, StudyRun).
    """
    design = full_factorial(nominal, levels=levels, rel_range=rel_range, factors=tuple(nominal))
    run = run_study(study_function, design, scheduler=scheduler, progress=progress)
    return analyse_sensitivity(design, speeds, run.outputs, extra_ranges_kmh), run
