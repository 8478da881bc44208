"""Headline numbers of a clamped component: first torsion/bending frequencies, static k,
the axes of eqs. (1)-(7) and the stiffness split of eq. (12)."""
from dataclasses import dataclass

import numpy as np

from motoflex_ros.errors import ModelError
from motoflex_ros.identify.decomposition import decompose_stiffness

__all__ = ["ComponentSummary", "summarize"]


@dataclass(frozen=True)
class ComponentSummary:
    """Summary of a clamped reduced component.

    dofs: full-model DOF count; modes: kept fixed-interface modes; f_torsion_hz,
    f_bending_hz [Hz]; k_static [N m/rad] (eq. 8); static_axis, torsion_axis, bending_axis
    (DeformationAxis: l [m], beta [rad], b [m]); k_t, k_b [N m/rad] (eq. 12, from the static
    axis and the mode-shape axes; NaN when a mode type is missing).
    """

    name: str
    dofs: int
    modes: int
    f_torsion_hz: float
    f_bending_hz: float
    k_static: float
    static_axis: object
    torsion_axis: object
    bending_axis: object
    k_t: float
    k_b: float


def _split(static, t_axis, b_axis):
    if t_axis is None or b_axis is None:
        return float("nan"), float("nan")
    a = static.axis
    values = (static.k, a.beta, a.b, t_axis.beta, t_axis.b, b_axis.beta, b_axis.b)
    if not np.all(np.isfinite(values)):
        return float("nan"), float("nan")
    try:
        s = decompose_stiffness(static.k, a.beta, a.b, t_axis.beta, t_axis.b, b_axis.beta,
                                b_axis.b)
    except ModelError:
        return float("nan"), float("nan")
    return s.k_t, s.k_b


def summarize(component, reduced=None, force=100.0):
    """ComponentSummary of a Component (reduced with the default Craig-Bampton settings)."""
    red = reduced if reduced is not None else component.clamped_reduced()
    static = red.static_lateral(force)
    axes = {lab: (red.mode_axis(lab) if red.first_mode(lab) is not None else None)
            for lab in ("torsion", "bending")}
    k_t, k_b = _split(static, axes["torsion"], axes["bending"])
    return ComponentSummary(name=component.name, dofs=component.dof_count(),
                            modes=int(red.n_modes), f_torsion_hz=red.frequency("torsion"),
                            f_bending_hz=red.frequency("bending"), k_static=static.k,
                            static_axis=static.axis, torsion_axis=axes["torsion"],
                            bending_axis=axes["bending"], k_t=float(np.real(k_t)),
                            k_b=float(np.real(k_b)))
