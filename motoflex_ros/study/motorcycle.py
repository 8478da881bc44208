"""The sensitivity study on the vehicle engine's decomposed lumped motorcycle (Sect. 4.3, 5.3).

The factors are the six joint stiffnesses of the "decomposed" variant (eq. 12: a torsion and a
bending joint per component, :mod:`motoflex_ros.vehicle.lumped`), nominal values from the
identification results ({component: {"k_t", "k_b", "torsion": {"l", "beta"}, "bending":
{...}}}). The nominal motorcycle is linearized once (E(v), A(v) as speed polynomials); each
stiffness enters A linearly (spring moment -k q and damper -gamma k q', neither depending on
speed), so the six directions dA/dk_i = dA_0/dk_i come from linearizations at v = 0 (where A is
A_0), checked for linearity, and every run's pencil is a sum
(:class:`motoflex_ros.study.tracked.LinearStiffnessPencil`); one direct linearization at the
highest speed checks that sum (speed-independent spring terms). Weave and wobble are named
by the engine's modal sweep of the nominal motorcycle (mode shape at its reference speed) and
tracked in every run by continuation.

Beyond the paper, the same study on the "principal" variant (:func:`principal_study`): the
factors are the principal hinges' stiffnesses (:mod:`motoflex_ros.identify.principal`), each
named after the paper's factor its axis stands for (t/b: within 45 deg of O-q0 or not, as the
component model's modes are labelled; f/a/s the component), so that their Pearson coefficients
can be set beside the flexible study's (:mod:`motoflex_ros.study.flexible_sensitivity`).
"""
from dataclasses import dataclass

import numpy as np

from motoflex_ros.errors import ConfigError, ModelError
from motoflex_ros.identify.measured import label_axis
from motoflex_ros.identify.results import ResultsFile, results_source
from motoflex_ros.study.factorial import FACTOR_DESCRIPTIONS, FACTORS
from motoflex_ros.study.identified_variants import (
    build_variant,
    check_principal,
    check_split_identifiable,
)
from motoflex_ros.study.tracked import pencil_study
from motoflex_ros.units import ms_to_kmh
from motoflex_ros.vehicle.dynamics import build_system
from motoflex_ros.vehicle.linearize import linearize, linearize_at
from motoflex_ros.vehicle.lumped import COMPONENTS
from motoflex_ros.vehicle.mode_names import STUDIED_MODES
from motoflex_ros.vehicle.modes import modal_sweep

__all__ = ["FACTOR_KEYS", "DIRECTION_SPEED", "MotorcycleStudy", "nominal_stiffness",
           "with_stiffness", "decomposed_study", "principal_factors", "with_principal_stiffness",
           "principal_study"]

# factor -> (component, key of the identification results)
FACTOR_KEYS = {f: (component, "k_t" if axis == "torsion" else "k_b")
               for f, (component, axis) in FACTOR_DESCRIPTIONS.items()}
DIRECTION_SPEED = 0.0
"""Speed [m/s] of the linearizations that give the stiffness directions dA_0/dk_i: at v = 0,
A(v) = A_0 + v A_1 + v^2 A_2 is exactly its speed-independent coefficient A_0, which is what
:func:`motoflex_ros.study.tracked.pencil_study` asks for."""


@dataclass(frozen=True, eq=False)
class MotorcycleStudy:
    """study: the study function; nominal: {factor: k} [N m/rad]; sweep: the engine's
    ModalSweep of the nominal motorcycle on the study's speeds."""

    study: object
    nominal: dict
    sweep: object


def nominal_stiffness(identified):
    """{factor: k} [N m/rad] from identification results (k_t, k_b of each component).

    ConfigError for a missing value; ModelError naming the component when its eq. (12) split
    is not identifiable (flagged, or not a positive finite number).
    """
    nominal = {}
    for factor in FACTORS:
        component, key = FACTOR_KEYS[factor]
        if not isinstance(identified.get(component), dict) or key not in identified[component]:
            raise ConfigError(results_source(identified), f"{component}.{key}",
                              "missing (run motoflex identify or give a complete file)")
        check_split_identifiable(identified, component)
        nominal[factor] = float(identified[component][key])
    return nominal


def with_stiffness(identified, values):
    """A copy of the identification results with k_t, k_b replaced by ``values`` ({factor: k}).

    A component whose k_t and k_b are both given no longer carries the identification's
    verdict on its eq. (12) split (the given values are judged instead).
    """
    out = {name: dict(result) for name, result in identified.items()}
    if isinstance(identified, ResultsFile):
        out = ResultsFile(out, identified.source)
    for factor, value in values.items():
        component, key = FACTOR_KEYS[factor]
        out[component][key] = float(value)
    for component, result in out.items():
        given = {FACTOR_KEYS[f] for f in values}
        if {(component, "k_t"), (component, "k_b")} <= given:
            result.pop("split_identifiable", None)
            result.pop("split_problem", None)
    return out


def _mode_targets(sweep):
    targets = []
    for mode in STUDIED_MODES:
        value = sweep.modes[mode][0]
        if not np.isfinite(value):
            raise ModelError(f"the nominal motorcycle's {mode} is not found at "
                             f"{ms_to_kmh(sweep.speeds[0]):.0f} km/h (modal sweep)")
        targets.append(complex(value))
    return targets


def principal_factors(identified):
    """{factor: (component, hinge index)} of the principal hinges of the three components:
    'k_<t|b><f|a|s>' after the hinge's axis (torsion within 45 deg of O-q0, else bending) and
    its component, 'k_p<i><f|a|s>' where two hinges of a component would share a name.

    ModelError naming the component when its principal hinges are not identified.
    """
    letters = {"frame": "f", "front_assembly": "a", "swingarm": "s"}
    out = {}
    for component in COMPONENTS:
        if not isinstance(identified.get(component), dict) or \
                "principal" not in identified[component]:
            raise ConfigError(results_source(identified), f"{component}.principal",
                              "missing (run motoflex identify with the moment tests)")
        check_principal(identified, component)
        for i, hinge in enumerate(identified[component]["principal"]["hinges"]):
            axis = label_axis(float(hinge["beta"]))[0]
            name = f"k_{axis}{letters[component]}"
            out[name if name not in out else f"k_p{i + 1}{letters[component]}"] = (component, i)
    return out


def with_principal_stiffness(identified, values, factors):
    """A copy of the identification results with the principal hinges' k replaced by
    ``values`` ({factor: k} [N m/rad]; ``factors`` from :func:`principal_factors`)."""
    out = {name: dict(result) for name, result in identified.items()}
    if isinstance(identified, ResultsFile):
        out = ResultsFile(out, identified.source)
    for component in {c for c, _ in factors.values()}:
        principal = dict(out[component]["principal"])
        principal["hinges"] = [dict(h) for h in principal["hinges"]]
        out[component]["principal"] = principal
    for factor, value in values.items():
        component, i = factors[factor]
        out[component]["principal"]["hinges"][i]["k"] = float(value)
    return out


def _lumped_study(vehicle, components, speeds, variant, nominal, results_of):
    """The pencil study of a lumped variant whose stiffnesses are the factors."""

    def model(values):
        return build_variant(vehicle, variant, list(COMPONENTS), results_of(values), components)

    lin = linearize(model(nominal))
    sweep = modal_sweep(lin, speeds)
    study = pencil_study(lin.E_coeffs, lin.A_coeffs,
                         lambda k: linearize_at(build_system(model(k)), DIRECTION_SPEED)[1],
                         nominal, speeds, _mode_targets(sweep),
                         reference=lambda k, v: linearize_at(build_system(model(k)), v))
    return MotorcycleStudy(study=study, nominal=nominal, sweep=sweep)


def principal_study(vehicle, components, identified, speeds):
    """The sensitivity study function of the principal lumped motorcycle (module doc):
    factors :func:`principal_factors`, nominal the identified hinges' k [N m/rad]."""
    factors = principal_factors(identified)
    nominal = {f: float(identified[c]["principal"]["hinges"][i]["k"])
               for f, (c, i) in factors.items()}
    return _lumped_study(vehicle, components, speeds, "principal", nominal,
                         lambda values: with_principal_stiffness(identified, values, factors))


def decomposed_study(vehicle, components, identified, speeds):
    """The sensitivity study function of the decomposed lumped motorcycle.

    Parameters
    ----------
    vehicle : VehicleModel
        The rigid motorcycle (e.g. the shipped "touring").
    components : mapping
        {component name: structures Component} placed in the motorcycle.
    identified : mapping
        Identification results of the three components.
    speeds : array
        Speed grid [m/s] (e.g. 40-210 km/h).

    """
    return _lumped_study(vehicle, components, speeds, "decomposed",
                         nominal_stiffness(identified),
                         lambda values: with_stiffness(identified, values))
