"""Steer-torque pulse response of the NONLINEAR equations of motion, integrated in time.

The engine's residual R(x', x; v, T) (:func:`motoflex_ros.vehicle.dynamics.residual`: Kane's
equations with the rolling, loop and lock constraints, tyre relaxation) is integrated as it is,
without linearizing it: at every evaluation the coordinates q(x) come from the contact-height
and loop-closure constraints (fixed-count Newton, :data:`POSITION_NEWTON_STEPS` steps from
q = 0), and x' from R(x', x) = 0 by Newton's method with the reference matrix
E_0 = dR/dx'(0) as iteration matrix, until the correction is below :data:`XDOT_RTOL` of x'.
R is affine in x' (the accelerations enter linearly), so E_0 only sets the convergence rate
(a contraction of about the motion's amplitude per iteration), never the answer. Time stepping:
the classical fourth-order Runge-Kutta method at the output sample period, the torque T on the
steer joint held over whole steps.

Nothing of the linearization (complex step, descriptor reduction, eigenvalues) is used: the
response is an independent check of it (:mod:`motoflex_ros.study.pulse_check`). Forward speed
v is held (the engine's longitudinal rolling constraint), as in the linear model.
"""
import numpy as np
import scipy.linalg

from motoflex_ros.errors import ModelError
from motoflex_ros.vehicle.dynamics import constraint_matrix, positions, residual
from motoflex_ros.vehicle.linearize import is_singular
from motoflex_ros.vehicle.response import PulseResponse, pulse_output_names

__all__ = ["nonlinear_steer_pulse", "POSITION_NEWTON_STEPS", "XDOT_RTOL"]

POSITION_NEWTON_STEPS = 3   # from q = 0: error O(|x|^8) for the small motions integrated here
XDOT_RTOL = 1e-9            # Newton on x': stop when the correction is below this share of x'
_MAX_XDOT_ITERATIONS = 30


def _reference_e(system, speed):
    """E_0 = dR/dx' at x = 0 [residual units]: exact by differences, R being affine in x'."""
    n = system.n_states
    zero = np.zeros(n)
    base = residual(system, zero, zero, speed)
    return np.column_stack([residual(system, e, zero, speed) - base for e in np.eye(n)])


def _derivative(system, x, speed, applied, lu, guess):
    """The derivative x' solving R(x', x; v, applied) = 0; ModelError if Newton stalls."""
    q = positions(system, x, POSITION_NEWTON_STEPS)
    G = constraint_matrix(system, q)
    xdot = guess.copy()
    for _ in range(_MAX_XDOT_ITERATIONS):
        step = scipy.linalg.lu_solve(lu, residual(system, xdot, x, speed, applied, q=q, G=G))
        xdot = xdot - step
        if np.max(np.abs(step)) <= XDOT_RTOL * max(np.max(np.abs(xdot)), 1e-300):
            return xdot
    raise ModelError(f"{system.model.source}: the nonlinear equations did not give x' in "
                     f"{_MAX_XDOT_ITERATIONS} Newton steps (motion too large for the pulse "
                     "check: use a smaller pulse)")


def nonlinear_steer_pulse(system, speed, torque=20.0, duration=0.05, t_end=1.5, dt=0.01,
                          outputs=None):
    """Response of the nonlinear vehicle to a steer-torque pulse (module docstring).

    Parameters
    ----------
    system : VehicleSystem
        The compiled vehicle (:func:`motoflex_ros.vehicle.dynamics.build_system`, or
        ``LinearVehicle.system``); its model's 'steer' role names the joint the torque acts on.
        Its E must be regular (no massless bodies).
    speed : float
        Forward speed v [m/s], held.
    torque, duration : float
        Pulse torque T [N m] on the steer joint and its duration [s] (rounded to whole steps).
    t_end, dt : float
        End time and the integration step, which is also the sample period [s]. The step's
        error on the eigenvalues read back from the response is about |lambda| (|lambda| dt)^4
        / 120 (fourth order): 0.1 % of wobble's real part at 100 km/h and dt = 0.01 s.
    outputs : sequence of str, optional
        State names to return; default as :func:`~motoflex_ros.vehicle.response.
        steer_pulse_response` (steer angle [rad], roll rate [rad/s], yaw rate [rad/s]).

    Returns
    -------
    PulseResponse
        Sampled states (state units) from the rest state at t = 0.

    Raises
    ------
    ModelError
        No 'steer' role, a singular E (massless bodies), an unknown output, or a motion too
        large for Newton's method on x'.

    """
    joint = system.model.roles.get("steer")
    if joint is None:
        raise ModelError(f"{system.model.source}: no 'steer' role to apply the pulse to")
    names = pulse_output_names(system, joint, outputs)
    rows = [system.state_names.index(name) for name in names]
    e_ref = _reference_e(system, speed)
    if is_singular(e_ref):
        raise ModelError(f"{system.model.source}: E is singular (massless bodies); the "
                         "nonlinear pulse response needs a regular E")
    lu = scipy.linalg.lu_factor(e_ref)
    steps = int(round(t_end / dt)) + 1
    pulse_steps = int(round(duration / dt))
    applied = np.zeros(len(system.tree.coordinates))
    steer = system.tree.index(joint)
    x = np.zeros(system.n_states)
    k4 = np.zeros(system.n_states)   # Newton on x' starts from the previous stage's x'
    out = np.empty((steps, len(rows)))
    for k in range(steps):
        out[k] = x[rows]
        if k == steps - 1:
            break
        applied[steer] = torque if k < pulse_steps else 0.0
        k1 = _derivative(system, x, speed, applied, lu, k4)
        k2 = _derivative(system, x + 0.5 * dt * k1, speed, applied, lu, k1)
        k3 = _derivative(system, x + 0.5 * dt * k2, speed, applied, lu, k2)
        k4 = _derivative(system, x + dt * k3, speed, applied, lu, k3)
        x = x + dt / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4)
    return PulseResponse(np.arange(steps) * dt, out, names, torque, pulse_steps * dt, speed)
