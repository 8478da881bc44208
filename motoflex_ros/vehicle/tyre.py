"""Tyres: linear tyre with relaxation, and the motorcycle Magic Formula linearized at a load.

The engine uses one linear tyre law per wheel (two relaxed states, side force F and aligning
moment M, written without dividing by speed so that the equations stay polynomial in v):

    sigma(v) F' = -K_alpha v_slip + v (K_gamma gamma - F)
    sigma(v) M' = +K_malpha v_slip + v (K_mgamma gamma - M)

v_slip [m/s] is the lateral velocity of the wheel's material point at the contact (to the left),
gamma [rad] the camber angle leaning to the left (REP-103), F [N] acts along the lateral axis of
the contact frame and M [N m] about the ground normal. Physically: the slip force opposes the
slip, the camber force points to the side the wheel leans to, the pneumatic trail turns the
wheel into its direction of travel, and the camber twisting moment turns it towards the lean
side. The relaxation length is sigma(v) = s0 + s1 v + s2 v^2 [m].

Magic Formula: Sharp, Evangelou & Limebeer (2004) motorcycle tyre as written in [MD] and [TUM]
(docs/references.md#sel2004; the [TUM] variant of the camber term inside the sine).
"""
from dataclasses import dataclass

import numpy as np

from motoflex_ros.config import validate
from motoflex_ros.errors import ConfigError
from motoflex_ros.vehicle.schema import MF_COEFFICIENTS, TYRE_SCHEMAS

__all__ = ["LinearTyre", "linear_tyre", "mf_side_force", "mf_aligning_moment", "mf_linearized",
           "tyre_from_config"]


@dataclass(frozen=True)
class LinearTyre:
    """Linear tyre with first-order relaxation (module docstring).

    k_alpha [N/rad] cornering stiffness, k_gamma [N/rad] camber stiffness, k_malpha [N m/rad]
    aligning stiffness (pneumatic trail times k_alpha), k_mgamma [N m/rad] camber twisting
    stiffness, sigma = (s0 [m], s1 [s], s2 [s^2/m]) relaxation length coefficients.
    """

    k_alpha: float
    k_gamma: float
    k_malpha: float
    k_mgamma: float
    sigma: tuple

    def relaxation_length(self, v):
        """sigma(v) = s0 + s1 v + s2 v^2 [m] at speed v [m/s]."""
        s0, s1, s2 = self.sigma
        return s0 + s1 * v + s2 * v * v


def linear_tyre(k_alpha, k_gamma=0.0, k_malpha=0.0, k_mgamma=0.0, relaxation_length=0.1):
    """A linear tyre with constant relaxation length [m]."""
    return LinearTyre(float(k_alpha), float(k_gamma), float(k_malpha), float(k_mgamma),
                      (float(relaxation_length), 0.0, 0.0))


def _cornering_stiffness(p, fz, gamma):
    """K_y,alpha [N/rad] = pky1 Fz0 sin(pky2 atan(Fz/((pky3 + pky4 g^2) Fz0))) / (1 + pky5 g^2)."""
    fz0 = p["Fz0"]
    g2 = gamma * gamma
    return (p["pky1"] * fz0 * np.sin(p["pky2"] * np.arctan(fz / ((p["pky3"] + p["pky4"] * g2)
                                                                 * fz0)))
            / (1.0 + p["pky5"] * g2))


def mf_side_force(p, fz, alpha, gamma):
    """Pure-slip side force Fy [N] of the motorcycle Magic Formula (sect. 1.4, [TUM] form).

    alpha [rad] slip angle and gamma [rad] camber in the Magic Formula's own sign convention
    (positive alpha and positive gamma both give positive Fy); fz [N] load; p coefficients.
    """
    dfz = (fz - p["Fz0"]) / p["Fz0"]
    dy = fz * p["pdy1"] * np.exp(p["pdy2"] * dfz) / (1.0 + p["pdy3"] * gamma * gamma)
    ey = p["pey1"] + p["pey2"] * gamma * gamma + p["pey4"] * gamma * np.sign(np.real(alpha))
    by = _cornering_stiffness(p, fz, gamma) / (p["Cy"] * dy)
    kg = (p["pky6"] + p["pky7"] * dfz) * fz
    bg = kg / (p["Cgamma"] * dy)
    slip = p["Cy"] * np.arctan(by * alpha - ey * (by * alpha - np.arctan(by * alpha)))
    camb = p["Cgamma"] * np.arctan(bg * gamma - p["Egamma"] * (bg * gamma - np.arctan(bg * gamma)))
    return dy * np.sin(slip + camb)


def mf_aligning_moment(p, fz, alpha, gamma, crown_radius):
    """Pure-slip aligning moment Mz [N m] (trail part plus camber residual, sect. 1.4).

    Signs as in the Magic Formula: Mz = -t Fy0(alpha, 0) + Mzr. The |gamma| terms use the
    real part of gamma (complex-step safe; the linearization at gamma = 0 does not use them).
    """
    fz0 = p["Fz0"]
    dfz = (fz - fz0) / fz0
    ag = np.abs(np.real(gamma))
    bt = (p["qbz1"] + p["qbz2"] * dfz) * (1.0 + p["qbz5"] * ag + p["qbz6"] * gamma * gamma)
    dt = fz * (crown_radius / fz0) * (p["qdz1"] + p["qdz2"] * dfz) * (
        1.0 + p["qdz3"] * ag + p["qdz4"] * gamma * gamma)
    et = (p["qez1"] + p["qez2"] * dfz) * (
        1.0 + p["qez5"] * gamma * (2.0 / np.pi) * np.arctan(bt * p["Ct"] * alpha))
    bta = bt * alpha
    trail = dt * np.cos(p["Ct"] * np.arctan(bta - et * (bta - np.arctan(bta))))
    trail = trail / np.sqrt(1.0 + alpha * alpha)
    by = _cornering_stiffness(p, fz, 0.0) / (p["Cy"] * fz * p["pdy1"] * np.exp(p["pdy2"] * dfz))
    br = p["qbz9"] + p["qbz10"] * by * p["Cy"]
    dr = fz * crown_radius * ((p["qdz8"] + p["qdz9"] * dfz) * gamma
                              + (p["qdz10"] + p["qdz11"] * dfz) * gamma * ag)
    dr = dr / np.sqrt(1.0 + alpha * alpha)
    alpha_r = alpha + (p["qhz3"] + p["qhz4"] * dfz) * gamma
    return -trail * mf_side_force(p, fz, alpha, 0.0) + dr * np.cos(np.arctan(br * alpha_r))


def mf_linearized(p, fz, crown_radius):
    """Linear tyre from the Magic Formula at load fz [N], alpha = gamma = 0 (closed form).

    K_alpha = Dy Cy By = K_y,alpha(Fz, 0); K_gamma = (pky6 + pky7 dfz) Fz; pneumatic trail
    t0 = Fz (R0/Fz0)(qdz1 + qdz2 dfz), K_malpha = t0 K_alpha; K_mgamma = Fz R0 (qdz8 + qdz9 dfz);
    relaxation length sigma(v) = K_alpha (a + b v + c v^2) (sect. 1.4). R0 is the crown radius.
    """
    fz0 = p["Fz0"]
    dfz = (fz - fz0) / fz0
    k_alpha = float(_cornering_stiffness(p, fz, 0.0))
    k_gamma = (p["pky6"] + p["pky7"] * dfz) * fz
    trail = fz * (crown_radius / fz0) * (p["qdz1"] + p["qdz2"] * dfz)
    k_mgamma = fz * crown_radius * (p["qdz8"] + p["qdz9"] * dfz)
    sigma = tuple(k_alpha * p[k] for k in ("relaxation_a", "relaxation_b", "relaxation_c"))
    return LinearTyre(k_alpha, float(k_gamma), float(trail * k_alpha), float(k_mgamma), sigma)


def tyre_from_config(spec, source, key, fz, crown_radius):
    """The LinearTyre of one wheel's ``tyre`` mapping, or None for a knife-edge wheel.

    fz [N] is the static wheel load (used by the Magic Formula), crown_radius [m].
    """
    model = spec["model"]
    spec = validate(spec, TYRE_SCHEMAS[model], source, key)
    if model == "knife_edge":
        return None
    if model == "linear":
        return linear_tyre(spec["cornering_stiffness"], spec["camber_stiffness"],
                           spec["aligning_stiffness"], spec["twisting_stiffness"],
                           spec["relaxation_length"])
    missing = [name for name in MF_COEFFICIENTS if spec[name] is None]
    if missing:
        raise ConfigError(source, f"{key}.{missing[0]}",
                          f"missing Magic Formula coefficient (required: {', '.join(missing)})")
    tyre = mf_linearized(spec, fz, crown_radius)
    if tyre.k_alpha <= 0.0:
        raise ConfigError(source, f"{key}.pky1", f"cornering stiffness at the static load "
                                                 f"Fz = {fz:.4g} N (Fz0 {spec['Fz0']:g} N; "
                                                 f"the load comes from the bodies' masses and "
                                                 f"the wheel positions) is {tyre.k_alpha:g} "
                                                 f"N/rad; must be > 0")
    return tyre
