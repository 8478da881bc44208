"""One evaluation of a design: mass, the four stability indices and the strength stand-ins.

Beyond the paper (issue 26). A design (the varied section dimensions [m] of a
:class:`~motoflex_ros.study.design_space.DesignSpace`) is evaluated on the flexible
motorcycle with all three components as superelements: the changed components are rebuilt
from their beam files and re-reduced, the motorcycle's E(v), A(v) updated exactly
(:mod:`motoflex_ros.study.design_update`), weave and wobble continued from the nominal
motorcycle to the design and then over 40-210 km/h by eigenpair continuation
(:mod:`motoflex_ros.study.tracked`), and the stability indices of eqs. (13)-(15) taken in
40-100 and 100-210 km/h (:mod:`motoflex_ros.study.stability_index`). Vectorised over designs:
the evaluator is a study function of :func:`motoflex_ros.study.runner.run_study` (values
{variable: array (runs,)}), so a batch runs in this process or on Dask alike.
"""
from dataclasses import dataclass, replace

import numpy as np

from motoflex_ros.structures.clamped import clamped_frequencies
from motoflex_ros.study.design_space import component_with, design_configs, members_mass
from motoflex_ros.study.design_update import design_engine
from motoflex_ros.study.motorcycle import _mode_targets
from motoflex_ros.study.sensitivity import stability_indices
from motoflex_ros.study.stability_index import INDEX_NAMES
from motoflex_ros.study.tracked import HomotopyStart, TrackedModeStudy
from motoflex_ros.vehicle.linearize import LinearVehicle
from motoflex_ros.vehicle.modes import modal_sweep

__all__ = ["DesignBatch", "StackedPencil", "DesignEvaluator", "design_evaluator",
           "STATIC_FORCE"]

STATIC_FORCE = 100.0
"""Lateral force of the static test that gives k [N] (the value of ``motoflex components``)."""


@dataclass(frozen=True)
class DesignBatch:
    """Designs as a design of :func:`~motoflex_ros.study.runner.run_study`: ``names`` of the
    variables and ``X`` (runs, variables) [m]."""

    names: tuple
    X: np.ndarray

    def __len__(self):
        return self.X.shape[0]

    def values(self, start=0, stop=None):
        """{variable: array (runs,)} [m] of runs start..stop."""
        block = np.atleast_2d(self.X)[start:stop]
        return {name: block[:, i].copy() for i, name in enumerate(self.names)}


@dataclass(frozen=True, eq=False)
class StackedPencil:
    """state_matrices of a TrackedModeStudy: E(v), A(v) (runs, n, n) from per-run
    speed-polynomial coefficients E_coeffs, A_coeffs (runs, degree + 1, n, n)."""

    E_coeffs: np.ndarray
    A_coeffs: np.ndarray

    def __call__(self, values, speed):
        powers = float(speed) ** np.arange(self.E_coeffs.shape[1])
        return (np.einsum("k,rkij->rij", powers, self.E_coeffs),
                np.einsum("k,rkij->rij", powers, self.A_coeffs))


@dataclass(frozen=True, eq=False)
class DesignEvaluator:
    """Study function {variable: array (runs,)} [m] -> {name: array (runs,)}.

    Outputs: "mass_kg" (the structural mass of the three components' members), the four
    indices (eq. 15), "mass_kg_<component>", "f1_hz_<component>" (first clamped
    eigenfrequency) and "k_static_<component>" [N m/rad] when ``static_k`` (k about the static
    axis, eq. 8; one more reduction per component).
    space: the DesignSpace; engine: the DesignEngine; speeds [m/s]; start: the nominal pencil
    at speeds[0] and weave and wobble's nominal eigenvalues there (HomotopyStart);
    held_mass_kg: members' mass of the components not varied.
    """

    space: object
    engine: object
    speeds: tuple
    start: object
    held_mass_kg: float
    static_k: bool = False

    def _one(self, x):
        configs = design_configs(self.space, x)
        comps = {c: component_with(cfg, self.space.sources[c]) for c, cfg in configs.items()}
        elements = self.engine.superelements(comps)
        out = {f"mass_kg_{c}": members_mass(cfg) for c, cfg in configs.items()}
        for c, se in elements.items():
            out[f"f1_hz_{c}"] = float(clamped_frequencies(se.M, se.K)[0] / (2.0 * np.pi))
            if self.static_k:
                reduced = comps[c].clamped_reduced(self.engine.n_modes[c], np.inf)
                out[f"k_static_{c}"] = float(reduced.static_lateral(STATIC_FORCE).k)
        out["mass_kg"] = self.held_mass_kg + sum(out[f"mass_kg_{c}"] for c in configs)
        return out, self.engine.coefficients(elements)

    def __call__(self, values):
        X = np.column_stack([np.asarray(values[n], float) for n in self.space.names])
        rows, E, A = [], [], []
        for x in X:
            out, (e, a) = self._one(x)
            rows.append(out)
            E.append(e)
            A.append(a)
        study = TrackedModeStudy(state_matrices=StackedPencil(np.array(E), np.array(A)),
                                 speeds=self.speeds, start=self.start)
        curves = study({"run": np.arange(len(X))})
        indices = stability_indices(np.asarray(self.speeds), curves)
        result = {name: np.array([r[name] for r in rows]) for name in rows[0]}
        result.update({name: indices[name].s for name in INDEX_NAMES})
        return result


def design_evaluator(space, vehicle, components, speeds, held_mass_kg, static_k=False):
    """The DesignEvaluator of ``space`` on the flexible ``vehicle`` (rigid VehicleModel) with
    ``components`` ({name: Component} of frame, front assembly and swingarm: the nominal
    design), over ``speeds`` [m/s] (40 to 210 km/h); ``held_mass_kg`` [kg] the members' mass of
    the components the space does not vary
    (:func:`motoflex_ros.formats.design_space_file.held_members_mass`)."""
    engine = design_engine(vehicle, components, space.components())
    lin = LinearVehicle(engine.system, engine.E_coeffs, engine.A_coeffs)
    sweep = modal_sweep(lin, np.asarray(speeds, float)[:1])
    e0, a0 = lin.pencil(np.asarray(speeds, float)[:1])
    start = HomotopyStart(nominal=(e0[0], a0[0]), targets=tuple(_mode_targets(sweep)))
    return DesignEvaluator(space, replace(engine, system=None), tuple(np.asarray(speeds, float)),
                           start, float(held_mass_kg), static_k)
