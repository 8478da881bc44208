"""The wrench a component carries in a mode of the flexible motorcycle (the "vehicle_load").

In the flexible motorcycle each component is a Craig-Bampton superelement whose loaded end
carries what the component carries (the steering joint on the frame's head, a wheel on the
front assembly's or the swingarm's axle, :mod:`motoflex_ros.vehicle.superelement`). Its
end-DOF rows of the equations of motion,

    f_end = [M x'' + M_xR a_P + C x' + K x - M_v^T R_P^T g]_end,

are the wrench (F_x, F_y, F_z, M_x, M_y, M_z) [N, N m] at q0 that the carried parts put on
the component: its elastic, damping and inertia forces together. In a mode (eigenvalue lambda,
eigenvector z of E x' = A x) they are f_end = (lambda F' + F) z with F', F the derivatives of
those rows by x' and x, found here by complex-step differentiation of the engine's own
residual (the element's rows recorded as the engine evaluates them), so nothing of the
engine is re-derived. The complex wrench is turned real at the phase where it is largest
(moments weighted by 1/|q0|); its direction is the load vector of the bench test
"vehicle_load" (:mod:`motoflex_ros.bench.load_tests`), scaled to the bench's static force.
"""
from dataclasses import dataclass, replace

import numpy as np

from motoflex_ros.errors import ModelError
from motoflex_ros.vehicle import lumped
from motoflex_ros.vehicle.dynamics import residual
from motoflex_ros.vehicle.linearize import COMPLEX_STEP
from motoflex_ros.vehicle.modes import modal_sweep
from motoflex_ros.vehicle.superelement import coordinate_names, end_body

__all__ = ["ModeWrench", "mode_wrench", "carried_element", "real_at_largest"]



@dataclass(frozen=True)
class ModeWrench:
    """The wrench a component carries in a mode: ``wrench`` (6,) real [N, N m] at q0 (vehicle
    axes), ``end_motion`` (6,) the loaded end's motion in the same phase [m, rad] (relative to
    the clamps), ``complex_wrench`` and ``complex_motion`` before the phase was chosen, the
    mode's ``eigenvalue`` [1/s] at ``speed`` [m/s], ``mode`` its name. The scale is the
    eigenvector's (largest state 1)."""

    component: str
    mode: str
    speed: float
    eigenvalue: complex
    wrench: np.ndarray
    end_motion: np.ndarray
    complex_wrench: np.ndarray
    complex_motion: np.ndarray

    @property
    def direction(self):
        """The wrench divided by the norm of its force [N/N, N m/N]."""
        return self.wrench / np.linalg.norm(self.wrench[:3])


def _carrier(model, component):
    kind, name = lumped.MOUNTS[component][1]
    if kind == "wheel":
        hits = [w.carrier for w in model.wheels if w.name == name]
    else:
        role = model.roles.get(name, name)
        hits = [j.parent for j in model.joints if j.name == role]
    if not hits:
        raise ModelError(f"vehicle '{model.name}' has no {kind} '{name}' (what component "
                         f"'{component}' carries)")
    return hits[0]


def carried_element(system, component):
    """(index, bound element) of the superelement of ``system`` whose loaded end carries what
    ``component`` carries (the body of the steering joint or the wheel)."""
    carrier = _carrier(system.model, component)
    for i, bound in enumerate(system.elements):
        element = getattr(bound, "element", bound)
        if hasattr(element, "M_xR") and end_body(element) == carrier:
            return i, bound
    raise ModelError(f"{system.model.name}: no superelement carries what '{component}' carries "
                     f"(body '{carrier}'); is the component flexible in this motorcycle?")


class _Recorder:
    """A bound element that keeps what it adds to the residual (the rows of interest)."""

    def __init__(self, bound, rows):
        self.bound, self.rows, self.last = bound, rows, None

    def generalized_residual(self, system, frames, q, u, udot):
        out = self.bound.generalized_residual(system, frames, q, u, udot)
        self.last = out[self.rows]
        return out


def real_at_largest(vector, weights):
    """Re(vector e^(i phi)) at the phase phi where its weighted norm is largest."""
    scaled = np.asarray(vector) * weights
    phi = -0.5 * np.angle(np.sum(scaled * scaled))
    return (np.asarray(vector) * np.exp(1j * phi)).real, phi


def mode_wrench(lin, component, speed, mode="wobble", length=1.0):
    """ModeWrench of ``component`` in ``mode`` of the flexible motorcycle ``lin`` (its
    LinearVehicle) at ``speed`` [m/s] (mode named and tracked by the engine's modal sweep);
    ``length`` [m] weights the moments (1/length) in choosing the phase (the component's
    |q0|)."""
    system = lin.system
    index, bound = carried_element(system, component)
    element = bound.element
    sweep = modal_sweep(lin, [float(speed)])
    lam, shape = complex(sweep.modes[mode][0]), sweep.mode_shapes[mode][0]
    if not np.isfinite(lam):
        raise ModelError(f"{system.model.name}: no {mode} at {speed:g} m/s")
    rows = np.asarray(bound.indices)[:6]
    recorder = _Recorder(bound, rows)
    probe = replace(system, elements=tuple(recorder if i == index else e
                                           for i, e in enumerate(system.elements)))
    parts = []
    for x, xdot in ((shape.real, (lam * shape).real), (shape.imag, (lam * shape).imag)):
        residual(probe, 1j * COMPLEX_STEP * xdot, 1j * COMPLEX_STEP * x, float(speed))
        parts.append(recorder.last.imag / COMPLEX_STEP)
    wrench = parts[0] + 1j * parts[1]
    names = list(lin.state_names)
    motion = np.array([shape[names.index(n)] for n in coordinate_names(element)[:6]])
    weights = np.r_[np.ones(3), np.full(3, 1.0 / float(length))]
    real, phi = real_at_largest(wrench, weights)
    return ModeWrench(component, mode, float(speed), lam, real,
                      (motion * np.exp(1j * phi)).real, wrench, motion)
