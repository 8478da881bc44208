"""Sensitivity of the per-body flexible motorcycle to the front joint links' tilt stiffness.

The per-body motorcycle (``--flex flexible_bodies``: the paper's Table A.1 bodies joined by the
rigid model's joints) has the Telelever's spherical head joint, so its fork bridge (with the
handlebars) rocks on the head, held only by the rotational stiffness of the two joint links
that seat the stanchion tops in the bridge: 300 N m/rad cardanic and torsional in
config/components/front_assembly.yaml, an estimate no source gives and the bench never loads
(its head clamp holds the bridge in all six directions). This study scales that stiffness by
factors s and tabulates weave and wobble over speed. Two ways (``part``): "tilt" scales the
cardanic stiffness only, about the axes normal to the stanchion (K_r' = D K_r D,
D = sqrt(s) P + a a^T, P = I - a a^T, a the stanchion's axis from its top to its upper
bushing; the torsion about the stanchion is left as it is); "rotation" scales the whole 3 x 3
rotational block (cardanic and torsional, D = sqrt(s) I: the earlier tool's sweep); the two
give the same weave and wobble to 1.4e-4 1/s (measured at s = 3 to 100): the tilt is what
matters. Beside them, two references that do not depend on s: the per-body
motorcycle with the head a revolute about the steering axis (the bridge held, as on the bench)
and the motorcycle with one clamped superelement per component (the default ground truth).

Limits. As s goes to zero the bridge's rocking stiffness at the head (head rotations freed,
FE bodies joined in structures/) goes to zero in proportion to s, the links alone holding it
(:func:`bridge_rocking_stiffness`), so a rocking mode's frequency scales as sqrt(s). As s grows
the structure in series (stanchions, slider bushings, lower fork) caps it (2.5e4 and 3.6e4
N m/rad at s = 1000): the weave goes to the held-bridge motorcycle's (e_RMS of its real part
0.8 % at s = 30, 0.1 % at 1000), the wobble does not (3.5 % at 30, 11 % at 1000): stiff links
are not the bench's clamp (docs/beyond-the-paper-checks.md). The rider's hands on the
handlebars, which would hold the bridge too, are not modelled.

Cost: one per-body linearization per factor (about 85 s on this machine, more when loaded),
the held-bridge one and the superelement one; minutes for a sweep, so it runs from the tool
(tools/front_bridge_rocking.py), not in the test suite.
"""
import copy
from dataclasses import dataclass, replace

import numpy as np

from motoflex_ros.structures.bodies import assemble_bodies, reduce_bodies
from motoflex_ros.study.identified_variants import build_variant
from motoflex_ros.vehicle.linearize import linearize
from motoflex_ros.vehicle.mode_names import STUDIED_MODES
from motoflex_ros.vehicle.modes import modal_sweep

__all__ = ["TiltSweep", "FRONT", "TILT_FACTORS", "JOINT_LINKS", "PARTS", "with_joint_link_tilt",
           "bridge_rocking_stiffness", "held_bridge", "tilt_sweep"]

FRONT = "front_assembly"
TILT_FACTORS = (1.0, 3.0, 10.0, 30.0, 100.0)
JOINT_LINKS = (("fork_top_left", "stanchion_top_left"), ("fork_top_right", "stanchion_top_right"))
_STANCHION_BELOW = {"stanchion_top_left": "stanchion_upper_bushing_left",
                    "stanchion_top_right": "stanchion_upper_bushing_right"}
PARTS = ("tilt", "rotation")


def _spring_index(component, a, b):
    """Index in ``component.structure.springs`` of the spring between nodes a and b."""
    nodes = {component.node_names[a], component.node_names[b]}
    return next(i for i, (n1, n2, _) in enumerate(component.structure.springs)
                if {n1, n2} == nodes)


def _scaling(component, stanchion, factor, part):
    """D (3, 3) of K_r' = D K_r D for one joint link (module docstring)."""
    if part not in PARTS:
        raise ValueError(f"part must be one of {PARTS}, got {part!r}")
    if part == "rotation":
        return np.sqrt(factor) * np.eye(3)
    xyz = component.structure.xyz
    names = component.node_names
    axis = np.asarray(xyz[names[stanchion]], float) - xyz[names[_STANCHION_BELOW[stanchion]]]
    axis = axis / np.linalg.norm(axis)
    along = np.outer(axis, axis)
    return np.sqrt(factor) * (np.eye(3) - along) + along


def with_joint_link_tilt(factor, component, part="tilt"):
    """The front assembly with its joint links' tilt (or whole rotational) stiffness scaled.

    Parameters
    ----------
    factor : float
        Multiplies the joint links' (:data:`JOINT_LINKS`) cardanic stiffness (300 N m/rad
        nominal) [-]; translations unchanged.
    component : Component
        The front assembly to start from (left unchanged).
    part : {"tilt", "rotation"}
        "tilt": the stiffness about the axes normal to the stanchion only; "rotation": the
        whole rotational block, the torsion about the stanchion too (module docstring).

    Returns
    -------
    Component
        A copy of ``component`` with the joint links changed.

    """
    component = replace(component, structure=copy.deepcopy(component.structure))
    springs = component.structure.springs
    for top, stanchion in JOINT_LINKS:
        i = _spring_index(component, top, stanchion)
        n1, n2, block = springs[i]
        scaled = np.array(block, float)
        d = _scaling(component, stanchion, factor, part)
        scaled[3:, 3:] = d @ scaled[3:, 3:] @ d
        springs[i] = (n1, n2, scaled)
    return component


def bridge_rocking_stiffness(front_assembly, factor=1.0, part="tilt"):
    """Eigenvalues [N m/rad] (ascending) of the fork bridge's rotational stiffness of the
    ``front_assembly`` (a structures Component) at its head node, the head spring's rotations
    freed (the Telelever's spherical head joint; translations kept), joint links' ``part`` at
    ``factor`` times nominal; FE bodies reduced and joined as the per-body motorcycle joins
    them (:func:`motoflex_ros.structures.bodies.assemble_bodies`).

    The inverse of the 3 x 3 rotational block of the bridge node's static compliance."""
    component = with_joint_link_tilt(factor, front_assembly, part)
    springs = component.structure.springs
    i = _spring_index(component, "steering_head", "fork_bridge")
    n1, n2, block = springs[i]
    freed = np.array(block, float)
    freed[3:, :] = 0.0
    freed[:, 3:] = 0.0
    springs[i] = (n1, n2, freed)
    joined = assemble_bodies(component, reduce_bodies(component))
    compliance = joined.static_compliance(component.node_names["fork_bridge"])[3:, 3:]
    return np.linalg.eigvalsh(np.linalg.inv(compliance))


def held_bridge(per_body):
    """The per-body VehicleModel with its 'steer' joint a revolute about the steering axis
    (the fork bridge held on the head as the bench's clamp holds it)."""
    return replace(per_body, joints=tuple(replace(j, kind="revolute") if j.name == "steer"
                                          else j for j in per_body.joints))


@dataclass(frozen=True)
class TiltSweep:
    """Weave and wobble [1/s] of the per-body motorcycle over tilt-stiffness factors.

    ``part`` ("tilt" or "rotation", :func:`with_joint_link_tilt`), ``factors`` (f,) [-],
    ``speeds`` (s,) [m/s]; ``modes`` {"weave", "wobble": complex
    (f, s)}, nan where the mode is not found; ``held`` and ``superelement`` {mode: complex
    (s,)}: the held-bridge and the one-superelement references."""

    part: str
    factors: np.ndarray
    speeds: np.ndarray
    modes: dict
    held: dict
    superelement: dict

    def least_damped(self):
        """{mode: (largest real part over the speeds (f,) [1/s], the speed there (f,) [m/s])};
        nan for a factor where the mode is named at no speed."""
        out = {}
        for mode, values in self.modes.items():
            found = np.isfinite(values)
            real = np.where(found, values.real, -np.inf)
            k = np.argmax(real, axis=1)
            rows = np.arange(len(k))
            none = ~found.any(axis=1)
            out[mode] = (np.where(none, np.nan, real[rows, k]),
                         np.where(none, np.nan, self.speeds[k]))
        return out


def _weave_wobble(model, speeds):
    sweep = modal_sweep(linearize(model), speeds)
    return {m: np.asarray(sweep.modes[m], complex) for m in STUDIED_MODES}


def tilt_sweep(vehicle, front_assembly, speeds, factors=TILT_FACTORS, part="tilt",
               progress=None):
    """Weave and wobble of the per-body motorcycle, front assembly flexible, over ``factors``.

    Parameters
    ----------
    vehicle : VehicleModel
        The rigid motorcycle (config/vehicles/touring.yaml).
    front_assembly : Component
        The nominal front assembly (config/components/front_assembly.yaml, as loaded).
    speeds : array (s,)
        Speeds [m/s].
    factors : sequence of float
        Multipliers of the joint links' stiffness (:func:`with_joint_link_tilt`).
    part : {"tilt", "rotation"}
        What the factors scale (:func:`with_joint_link_tilt`).
    progress : callable, optional
        Called with a label before each linearization (they take minutes in all).

    Returns
    -------
    TiltSweep

    """
    speeds = np.asarray(speeds, float)
    say = progress or (lambda label: None)
    nominal = {FRONT: front_assembly}
    say("one clamped superelement")
    superelement = _weave_wobble(build_variant(vehicle, "flexible", [FRONT], {}, nominal), speeds)
    say("per-body, head revolute (bridge held)")
    per_body = build_variant(vehicle, "flexible_bodies", [FRONT], {}, nominal)
    held = _weave_wobble(held_bridge(per_body), speeds)
    rows = []
    for factor in factors:
        say(f"per-body, joint links' {part} x {factor:g}")
        model = build_variant(vehicle, "flexible_bodies", [FRONT], {},
                              {FRONT: with_joint_link_tilt(factor, front_assembly, part)})
        rows.append(_weave_wobble(model, speeds))
    modes = {m: np.array([row[m] for row in rows]) for m in STUDIED_MODES}
    return TiltSweep(part, np.asarray(factors, float), speeds, modes, held, superelement)
