"""Headline numbers of a clamped component: first torsion/bending frequencies, static k,
the axes of eqs. (1)-(7) and the stiffness split of eq. (12).

The frequencies are the clamped reduced (Craig-Bampton) model's, which the bench and the
vehicle use; the full clamped model's are given beside them, and a warning says when the
reduced model keeps no fixed-interface mode or is off by more than REDUCED_TOLERANCE."""
from dataclasses import dataclass

import numpy as np

from motoflex_ros.errors import ModelError
from motoflex_ros.lumped_stiffness.decomposition import decompose_stiffness
from motoflex_ros.structures.full_model import full_clamped_modes

__all__ = ["ComponentSummary", "summarize", "reduced_model_warnings", "REDUCED_TOLERANCE"]

REDUCED_TOLERANCE = 0.005  # issue 3: the reduced model's frequencies within 0.5 % of the full


@dataclass(frozen=True)
class ComponentSummary:
    """Summary of a clamped reduced component.

    dofs: full-model DOF count; modes: kept fixed-interface modes; f_torsion_hz,
    f_bending_hz [Hz]; k_static [N m/rad] (eq. 8); static_axis, torsion_axis, bending_axis
    (DeformationAxis: l [m], beta [rad], b [m]); k_t, k_b [N m/rad] (eq. 12, from the static
    axis and the mode-shape axes; NaN when a mode type is missing); f_torsion_full_hz,
    f_bending_full_hz [Hz] the same modes of the full clamped model; warnings (str) when the
    reduced model keeps no fixed-interface mode or its frequencies are off the full model's.
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
    f_torsion_full_hz: float = float("nan")
    f_bending_full_hz: float = float("nan")
    warnings: tuple = ()


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


def reduced_model_warnings(name, n_modes, reduced_hz, full_hz):
    """Warnings about the reduced model's frequencies against the full model's.

    Parameters
    ----------
    name : str
        Component name.
    n_modes : int
        Fixed-interface modes the reduced model keeps.
    reduced_hz, full_hz : dict
        First frequency [Hz] by mode label ('torsion', 'bending') of each model (NaN: none).

    Returns
    -------
    tuple of str
        One warning when no fixed-interface mode is kept, one per frequency off by more than
        REDUCED_TOLERANCE (relative) or found in only one of the models.

    """
    out = []
    if n_modes == 0:
        out.append(f"{name}: the reduced model keeps no fixed-interface mode (all above the "
                   f"cut-off); its frequencies come from the static constraint modes alone")
    for label, reduced in reduced_hz.items():
        full = full_hz[label]
        if np.isfinite(reduced) and np.isfinite(full):
            if abs(reduced / full - 1.0) > REDUCED_TOLERANCE:
                out.append(f"{name}: reduced-model f_{label} {reduced:.1f} Hz is "
                           f"{reduced / full - 1.0:+.2%} off the full model's {full:.1f} Hz")
        elif np.isfinite(reduced) != np.isfinite(full):
            out.append(f"{name}: f_{label} found in only one model (reduced {reduced:.1f} Hz, "
                       f"full {full:.1f} Hz)")
    return tuple(out)


def summarize(component, reduced=None, force=100.0):
    """ComponentSummary of a Component (reduced with the default Craig-Bampton settings), with
    the full clamped model's frequencies beside the reduced model's."""
    red = reduced if reduced is not None else component.clamped_reduced()
    full = full_clamped_modes(component)
    labels = ("torsion", "bending")
    reduced_hz = {lab: red.frequency(lab) for lab in labels}
    full_hz = {lab: full.frequency(lab) for lab in labels}
    static = red.static_lateral(force)
    axes = {lab: (red.mode_axis(lab) if red.first_mode(lab) is not None else None)
            for lab in ("torsion", "bending")}
    k_t, k_b = _split(static, axes["torsion"], axes["bending"])
    return ComponentSummary(name=component.name, dofs=component.dof_count(),
                            modes=int(red.n_modes), f_torsion_hz=red.frequency("torsion"),
                            f_bending_hz=red.frequency("bending"), k_static=static.k,
                            static_axis=static.axis, torsion_axis=axes["torsion"],
                            bending_axis=axes["bending"], k_t=float(np.real(k_t)),
                            k_b=float(np.real(k_b)), f_torsion_full_hz=full_hz["torsion"],
                            f_bending_full_hz=full_hz["bending"],
                            warnings=reduced_model_warnings(component.name, int(red.n_modes),
                                                            reduced_hz, full_hz))
