"""A lumped hinge in a component's symmetry plane, as the fitted variant handles it.

The hinge of the paper's eqs. (5)-(8): axis angle beta [rad] to the line O-q0, joint distance l
[m] along it, arm b = (L - l) sin beta [m] (eq. 7), stiffness k [N m/rad] and c = gamma k
(gamma = 0.001 s, the static models' damping). Beside the identification's (l, beta, k) the fit
(:mod:`motoflex_ros.study.fitted`) moves a hinge as a line (beta and the signed arm b of q0), turns
it about its point nearest q0 or shifts it normal to itself (:func:`perturbed`), and compares its
compliance with the clamped FE model's (:func:`end_compliance`).
"""
import math
from dataclasses import dataclass

import numpy as np

from motoflex_ros.errors import ModelError
from motoflex_ros.study.identified_variants import GAMMA

__all__ = ["Hinge", "site_plane", "hinge_from_line", "hinge_line", "hinge_compliance",
           "perturbed", "hinge_of", "static_hinge", "end_compliance"]


@dataclass(frozen=True)
class Hinge:
    """A hinge in the component frame as the paper gives it (eqs. 5-8): l [m] along O-q0, beta
    [rad] to O-q0, b [m] = (L - l) sin beta, k [N m/rad], c [N m s/rad] = gamma k."""

    l: float
    beta: float
    b: float
    k: float

    @property
    def c(self):
        """Damping [N m s/rad] of the static models, gamma k."""
        return GAMMA * self.k

    def to_dict(self):
        """{"l", "beta", "b", "k", "c"} (the keys of an identified static model)."""
        return {"l": self.l, "beta": self.beta, "b": self.b, "k": self.k, "c": self.c}


def site_plane(site):
    """(L [m], theta0 [rad]): length and angle of O-q0 in the component's x-z plane."""
    q0 = np.asarray(site.q0, float)
    return math.hypot(q0[0], q0[2]), math.atan2(q0[2], q0[0])


def hinge_from_line(site, beta, b, k):
    """Hinge with axis angle ``beta`` [rad] and signed arm ``b`` [m] of q0 (l = L - b/sin beta)."""
    length, _ = site_plane(site)
    turns = math.floor(beta / math.pi)       # the same line with the axis reversed: b flips
    beta, b = beta - turns * math.pi, b * (-1.0) ** turns
    s = math.sin(beta)
    if abs(s) < 1e-9:
        raise ModelError(f"component '{site.name}': a hinge parallel to O-q0 has no l")
    return Hinge(length - b / s, float(beta), float(b), float(k))


def hinge_line(site, hinge):
    """(point [m], unit axis) in the vehicle frame: the axis's point nearest q0, q0 + b n."""
    _, theta0 = site_plane(site)
    angle = theta0 + hinge.beta
    axis = np.array([math.cos(angle), 0.0, math.sin(angle)])
    normal = np.array([-math.sin(angle), 0.0, math.cos(angle)])
    return site.origin + site.q0 + hinge.b * normal, axis


def hinge_compliance(site, hinge, wrench):
    """The hinge's compliance w . C_h . w [m/N] under the wrench w = ``wrench`` (F [N], M [N m]
    at q0, vehicle axes): C_h = s s^T / k, s = (a x (q0 - p), a) its unit twist at q0."""
    point, axis = hinge_line(site, hinge)
    twist = np.concatenate([np.cross(axis, site.origin + site.q0 - point), axis])
    return float(twist @ np.asarray(wrench, float)) ** 2 / hinge.k


def perturbed(site, hinge, what, change):
    """The hinge with k scaled by ``change`` (what "k"), or beta or b shifted by it [rad, m]
    (the axis turned about its point nearest q0, or moved normal to itself)."""
    if what == "k":
        return Hinge(hinge.l, hinge.beta, hinge.b, hinge.k * change)
    if what == "beta":
        return hinge_from_line(site, hinge.beta + change, hinge.b, hinge.k)
    if what == "b":
        return hinge_from_line(site, hinge.beta, hinge.b + change, hinge.k)
    raise ValueError(f"unknown hinge parameter '{what}'")


def hinge_of(values):
    """Hinge from a model's values {"l", "beta", "b", "k", ...} (an identified static model)."""
    return Hinge(float(values["l"]), float(values["beta"]), float(values["b"]),
                 float(values["k"]))


def static_hinge(identified, component, site):
    """The identified static hinge (l, beta, k; b from eq. 7 on the component's q0)."""
    static = identified[component]["static"]
    length, _ = site_plane(site)
    beta = float(static["beta"])
    return Hinge(float(static["l"]), beta, (length - float(static["l"])) * math.sin(beta),
                 float(static["k"]))



def end_compliance(component):
    """C (6, 6): the clamped FE model's loaded-end motion (u [m], theta [rad]) per unit wrench
    (F [N], M [N m]) at q0 (the bench's reduced model; symmetrized, vehicle axes)."""
    reduced = component.clamped_reduced()
    c = np.column_stack([reduced.static_end_motion(e) for e in np.eye(6)])
    return 0.5 * (c + c.T)
