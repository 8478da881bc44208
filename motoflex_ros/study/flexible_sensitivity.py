"""The sensitivity study of Sect. 5.3 on the flexible ground truth (beyond the paper, issue 14).

The paper's 2^6 factorial scales the six lumped stiffnesses k_t, k_b of the decomposed model.
Here the same design scales the flexible motorcycle's structure: factor i multiplies by s_i
the modal stiffness omega_i^2 of its component's first torsion or first bending mode of the
clamped model (Table 1's modes) by the rank-one update of the superelement's stiffness

    K' = K + (s - 1) omega_i^2 (M phi_i)(M phi_i)^T,    phi_i mass-normalised,

which gives mode i the eigenvalue s omega_i^2 and leaves every other mode, the mass and the
(modal) damping matrix unchanged (MODAL_STIFFNESS). K x enters the equations of motion only in
the superelement's own rows (its coordinates are independent), so dA/ds_i is
-omega_i^2 (M phi_i)(M phi_i)^T in those rows and columns, exactly; the superposed pencils are
checked against a direct linearization at the highest speed (every s = 1.1), weave and wobble
are named by the engine's modal sweep of the nominal motorcycle and tracked in every run by
continuation (:func:`motoflex_ros.study.tracked.TrackedModeStudy`), as in the lumped study.
"""
from dataclasses import replace

import numpy as np

from motoflex_ros.errors import ModelError
from motoflex_ros.study.factorial import FACTOR_DESCRIPTIONS, FACTORS
from motoflex_ros.study.identified_variants import build_variant
from motoflex_ros.study.motorcycle import MotorcycleStudy, _mode_targets
from motoflex_ros.study.tracked import (
    HomotopyStart,
    LinearStiffnessPencil,
    TrackedModeStudy,
    check_pencil,
)
from motoflex_ros.study.vehicle_load import carried_element
from motoflex_ros.vehicle.dynamics import build_system
from motoflex_ros.vehicle.linearize import linearize, linearize_at
from motoflex_ros.vehicle.lumped import COMPONENTS
from motoflex_ros.vehicle.modes import modal_sweep
from motoflex_ros.vehicle.superelement import coordinate_names

__all__ = ["MODAL_STIFFNESS", "flexible_study", "modal_stiffness_update", "scaled_motorcycle"]

MODAL_STIFFNESS = (
    "flexible model: each factor s scales the modal stiffness omega_i^2 of its component's "
    "first torsion or first bending mode of the clamped model (Table 1): K' = K + (s - 1) "
    "omega_i^2 (M phi_i)(M phi_i)^T, phi_i mass-normalised; every other mode, M and C "
    "unchanged; nominal s = 1")


def modal_stiffness_update(component, element, label):
    """dK/ds (n, n) of the superelement ``element`` for the first ``label`` ('torsion' or
    'bending') mode of the clamped ``component`` (structures Component) [N/m..]."""
    reduced = component.clamped_reduced()
    if reduced.M.shape != element.M.shape or not np.allclose(reduced.M, element.M,
                                                               rtol=1e-9, atol=0.0):
        raise ModelError(f"component '{component.name}': its superelement is not the clamped "
                         "reduced model the modes come from")
    mode = reduced.first_mode(label)
    if mode is None:
        raise ModelError(f"component '{component.name}' has no {label} mode")
    phi = reduced.mode_shapes[:, mode]
    mass_phi = element.M @ phi
    omega2 = float(phi @ element.K @ phi)
    return omega2 * np.outer(mass_phi, mass_phi)


def scaled_motorcycle(model, updates, values):
    """The flexible ``model`` with each superelement's K + sum (s_i - 1) dK/ds_i.

    ``updates``: {factor: (element name, dK/ds)}; ``values``: {factor: s}."""
    elements = []
    for element in model.elements:
        change = sum(((float(values[f]) - 1.0) * d for f, (name, d) in updates.items()
                      if name == element.name), np.zeros_like(element.K))
        elements.append(replace(element, K=element.K + change) if np.any(change) else element)
    return replace(model, elements=tuple(elements))


def flexible_study(vehicle, components, identified, speeds):
    """The sensitivity study function of the flexible motorcycle (module docstring).

    Returns a MotorcycleStudy: ``study`` maps {factor: s (runs,)} to weave and wobble over
    ``speeds`` [m/s]; ``nominal`` {factor: 1.0}; ``sweep`` the nominal modal sweep at the
    first speed. ``identified`` is needed only to build the motorcycle (the flexible variant
    reads none of it).
    """
    model = build_variant(vehicle, "flexible", list(COMPONENTS), identified, components)
    lin = linearize(model)
    system = lin.system
    names = list(system.state_names)
    directions, updates = {}, {}
    for factor in FACTORS:
        component, label = FACTOR_DESCRIPTIONS[factor]
        _, bound = carried_element(system, component)
        element = bound.element
        update = modal_stiffness_update(components[component], element, label)
        coords = coordinate_names(element)
        rows = [names.index(f"{c}_rate") for c in coords]
        cols = [names.index(c) for c in coords]
        direction = np.zeros((system.n_states, system.n_states))
        direction[np.ix_(rows, cols)] = -update
        directions[factor], updates[factor] = direction, (element.name, update)
    nominal = {f: 1.0 for f in FACTORS}
    pencil = LinearStiffnessPencil(lin.E_coeffs, lin.A_coeffs, directions, nominal)
    check_pencil(pencil, lambda values, v: linearize_at(
        build_system(scaled_motorcycle(model, updates, values)), v),
        {f: 1.1 for f in FACTORS}, float(np.max(speeds)))
    sweep = modal_sweep(lin, np.asarray(speeds, float)[:1])
    e0, a0 = pencil({f: np.array([1.0]) for f in FACTORS}, speeds[0])
    start = HomotopyStart(nominal=(e0[0], a0[0]), targets=tuple(_mode_targets(sweep)))
    study = TrackedModeStudy(state_matrices=pencil, speeds=tuple(np.asarray(speeds, float)),
                             start=start)
    return MotorcycleStudy(study=study, nominal=nominal, sweep=sweep)
