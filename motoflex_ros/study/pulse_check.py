"""Independent check of the linearized eigenvalues in the time domain.

Integrate the vehicle's NONLINEAR equations after a small steer-torque pulse
(:func:`motoflex_ros.vehicle.nonlinear_response.nonlinear_steer_pulse`), read the poles of the
free response after the pulse by the matrix pencil (:func:`motoflex_ros.identify.matrix_pencil.
matrix_pencil_poles` on every state scaled by :func:`~motoflex_ros.identify.matrix_pencil.
unit_peak`, model order from the singular values) and compare the poles nearest weave and
wobble with the eigenvalues of the engine's linearization at that speed
(:func:`motoflex_ros.vehicle.modes.modal_sweep`, tracked by mode shape).

What it checks: the linearization (complex-step E and A, descriptor form, eigenvalues, mode
naming) against the equations it linearizes, by a route that shares nothing with it but the
residual. The two agree to the amplitude-dependent part of the motion (the nonlinear terms),
the integration error of the time step and the pencil's error on a response that is not
exactly a sum of exponentials; at 100 km/h after 20 N m x 0.05 s on the touring motorcycle
(steer up to 1 deg, roll 1.3 deg) all three together stay below 0.3 % on frequency and real
part of weave and wobble (docs/beyond-the-paper-checks.md).
"""
from dataclasses import dataclass

import numpy as np

from motoflex_ros.identify.matrix_pencil import matrix_pencil_poles, unit_peak
from motoflex_ros.vehicle.mode_names import STUDIED_MODES
from motoflex_ros.vehicle.modes import modal_sweep
from motoflex_ros.vehicle.nonlinear_response import nonlinear_steer_pulse

__all__ = ["PulseCheck", "pulse_check"]



@dataclass(frozen=True)
class PulseCheck:
    """Eigenvalues of the linearization (``linear``) and poles read from the nonlinear pulse
    response (``nonlinear``), {mode: complex [1/s]}, at ``speed`` [m/s] after ``torque`` [N m]
    over ``duration`` [s]; ``peak`` {state name: largest |value| of the response [state
    units]}: how small the motion was; ``response`` the nonlinear PulseResponse (every
    state)."""

    speed: float
    torque: float
    duration: float
    linear: dict
    nonlinear: dict
    peak: dict
    response: object

    def relative_errors(self):
        """{mode: (frequency error, real-part error)} of the nonlinear poles [-], each relative
        to the linear eigenvalue's imaginary and real part."""
        return {m: ((self.nonlinear[m].imag - lam.imag) / abs(lam.imag),
                    (self.nonlinear[m].real - lam.real) / abs(lam.real))
                for m, lam in self.linear.items()}


def pulse_check(lin, speed, torque=20.0, duration=0.05, t_end=1.5, dt=0.01):
    """Weave and wobble of the nonlinear pulse response against the linearized eigenvalues.

    Parameters
    ----------
    lin : LinearVehicle
        The linearized vehicle (:func:`motoflex_ros.vehicle.linearize.linearize`); the
        integration uses only its compiled nonlinear model ``lin.system``.
    speed : float
        Forward speed [m/s].
    torque, duration : float
        Steer-torque pulse [N m] and its length [s]; small, so that the motion stays in the
        linear range (the default, 20 N m x 0.05 s, is the review's).
    t_end, dt : float
        Length of the record and sample period = integration step [s]. Cost: 4 t_end / dt
        evaluations of the nonlinear derivative (each a position solve and 3-4 residuals): about
        6 s of CPU for the touring motorcycle with the defaults on this machine (2,061
        residuals), more wall time when the machine is shared.

    Returns
    -------
    PulseCheck
        A mode the linearization does not find at ``speed`` is left out.

    """
    response = nonlinear_steer_pulse(lin.system, speed, torque, duration, t_end, dt,
                                     outputs=lin.state_names)
    free = response.outputs[response.time >= response.duration]
    poles = matrix_pencil_poles(unit_peak(free), dt)
    sweep = modal_sweep(lin, [speed])
    linear = {m: complex(sweep.modes[m][0]) for m in STUDIED_MODES
              if np.isfinite(sweep.modes[m][0])}
    nonlinear = {m: complex(poles[np.argmin(np.abs(poles - lam))]) for m, lam in linear.items()}
    peak = dict(zip(response.output_names, np.max(np.abs(response.outputs), axis=0)))
    return PulseCheck(speed, torque, response.duration, linear, nonlinear, peak, response)
