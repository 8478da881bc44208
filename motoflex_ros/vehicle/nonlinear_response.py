"""Steer-torque pulse response of the NONLINEAR equations of motion, integrated in time.

The engine's residual R(x', x; v, T) (:func:`motoflex_ros.vehicle.dynamics.residual`: Kane's
equations with the rolling, loop and lock constraints, tyre relaxation) is integrated as it is,
without linearizing it: at every evaluation the coordinates q(x) come from the contact-height
and loop-closure constraints (fixed-count Newton, :data:`POSITION_NEWTON_STEPS` steps from
q = 0), and x' from R(x', x) = 0 by Newton's method with the reference matrix
E_0 = dR/dx'(0) as iteration matrix, until the correction is below :data:`XDOT_RTOL` of x'
(or :data:`XDOT_ATOL`).
R is affine in x' (the accelerations enter linearly), so E_0 only sets the convergence rate
(a contraction of about the motion's amplitude per iteration), never the answer; where it
contracts too slowly (an ill-conditioned E, e.g. a massless body carrying a wheel), E is
recomputed at the current state after :data:`REFRESH_AFTER` steps and kept. Time stepping:
the classical fourth-order Runge-Kutta method at the output sample period (or a whole fraction
of it where the fastest motion needs it, :func:`rk4_substeps`), the torque T on the steer joint
held over whole sample periods.

Nothing of the linearization (complex step, descriptor reduction, eigenvalues) is used: the
response is an independent check of it (:mod:`motoflex_ros.study.pulse_check`). Forward speed
v is held (the engine's longitudinal rolling constraint), as in the linear model.
"""
import numpy as np
import scipy.linalg

from motoflex_ros.errors import ModelError
from motoflex_ros.vehicle.dynamics import constraint_matrix, positions, residual
from motoflex_ros.vehicle.linearize import is_singular
from motoflex_ros.vehicle.steer_pulse import PulseResponse, pulse_output_names

__all__ = ["nonlinear_steer_pulse", "rk4_substeps", "POSITION_NEWTON_STEPS", "XDOT_RTOL",
           "XDOT_ATOL", "REFRESH_AFTER", "RK4_RATE_LIMIT"]

POSITION_NEWTON_STEPS = 3   # from q = 0: error O(|x|^8) for the small motions integrated here
XDOT_RTOL = 1e-9            # Newton on x': stop when the correction is below this share of x'
XDOT_ATOL = 1e-12           # ... or below this (state units per second): x' = 0 at rest
RK4_RATE_LIMIT = 2.0        # |lambda| h kept below this (RK4 is stable to about 2.8)
_JACOBIAN_STEP = 1e-6
REFRESH_AFTER = 6           # Newton steps on x' before E is recomputed at the current state
_MAX_XDOT_ITERATIONS = 12


def _e_matrix(system, x, speed, applied=None, q=None, G=None):
    """E(x) = dR/dx' at the state x [residual units]: exact by differences, R being affine in
    x'."""
    base = residual(system, np.zeros_like(x), x, speed, applied, q=q, G=G)
    return np.column_stack([residual(system, e, x, speed, applied, q=q, G=G) - base
                            for e in np.eye(system.n_states)])


def _factor(system, e_matrix):
    if is_singular(e_matrix):
        raise ModelError(f"{system.model.source}: E is singular (massless bodies); the "
                         "nonlinear pulse response needs a regular E")
    return scipy.linalg.lu_factor(e_matrix)


def _derivative(system, x, speed, applied, chord, guess):
    """The derivative x' solving R(x', x; v, applied) = 0 by Newton's method with the iteration
    matrix ``chord["lu"]`` (LU of E at some state); after :data:`REFRESH_AFTER` steps without
    convergence E(x) replaces it (then one step is exact, R being affine in x'), and is kept
    for the next calls. ModelError if that does not converge either."""
    q = positions(system, x, POSITION_NEWTON_STEPS)
    G = constraint_matrix(system, q)
    xdot = guess.copy()
    for k in range(_MAX_XDOT_ITERATIONS):
        if k == REFRESH_AFTER:
            chord["lu"] = _factor(system, _e_matrix(system, x, speed, applied, q, G))
            chord["refreshed"] += 1
        step = scipy.linalg.lu_solve(chord["lu"], residual(system, xdot, x, speed, applied,
                                                           q=q, G=G))
        xdot = xdot - step
        if np.max(np.abs(step)) <= max(XDOT_RTOL * np.max(np.abs(xdot)), XDOT_ATOL):
            return xdot
    raise ModelError(f"{system.model.source}: the nonlinear equations did not give x' in "
                     f"{_MAX_XDOT_ITERATIONS} Newton steps (motion too large for the pulse "
                     "check: use a smaller pulse)")


def rk4_substeps(system, speed, dt, chord=None):
    """Runge-Kutta steps per sample period ``dt`` [s] that keep the fastest motion stable:
    ceil(rho dt / :data:`RK4_RATE_LIMIT`), rho [1/s] the spectral radius of the Jacobian of x'
    at rest, by forward differences of the nonlinear derivative (only the step size depends on
    it, never the response). Stiff lumped hinges (|lambda| up to 750 1/s) need several; the
    rigid touring motorcycle (124 1/s) one at dt = 0.01 s."""
    n = system.n_states
    if chord is None:
        chord = {"lu": _factor(system, _e_matrix(system, np.zeros(n), speed)), "refreshed": 0}
    zero, free = np.zeros(n), np.zeros(len(system.tree.coordinates))
    base = _derivative(system, zero, speed, free, chord, zero)
    jac = np.column_stack([(_derivative(system, _JACOBIAN_STEP * e, speed, free, chord, base)
                            - base) / _JACOBIAN_STEP for e in np.eye(n)])
    rho = float(np.max(np.abs(np.linalg.eigvals(jac))))
    return max(1, int(np.ceil(rho * dt / RK4_RATE_LIMIT)))


def nonlinear_steer_pulse(system, speed, torque=20.0, duration=0.05, t_end=1.5, dt=0.01,
                          outputs=None):
    """Response of the nonlinear vehicle to a steer-torque pulse (module docstring).

    Parameters
    ----------
    system : VehicleSystem
        The compiled vehicle (:func:`motoflex_ros.vehicle.dynamics.build_system`, or
        ``LinearVehicle.system``); its model's 'steer' role names the joint the torque acts on.
        Its E must be regular (no massless body that carries nothing).
    speed : float
        Forward speed v [m/s], held.
    torque, duration : float
        Pulse torque T [N m] on the steer joint and its duration [s] (rounded to whole steps).
    t_end, dt : float
        End time and the sample period [s]; the Runge-Kutta step is dt or, where the fastest
        motion needs it, a whole fraction of it (:func:`rk4_substeps`). The step's error on
        the eigenvalues read back from the response is about |lambda| (|lambda| h)^4 / 120
        (fourth order): 0.1 % of wobble's real part at 100 km/h and h = 0.01 s.
    outputs : sequence of str, optional
        State names to return; default as :func:`~motoflex_ros.vehicle.steer_pulse.
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
    chord = {"lu": _factor(system, _e_matrix(system, np.zeros(system.n_states), speed)),
             "refreshed": 0}
    steps = int(round(t_end / dt)) + 1
    pulse_steps = int(round(duration / dt))
    applied = np.zeros(len(system.tree.coordinates))
    steer = system.tree.index(joint)
    x = np.zeros(system.n_states)
    k4 = np.zeros(system.n_states)   # Newton on x' starts from the previous stage's x'
    out = np.empty((steps, len(rows)))
    substeps = rk4_substeps(system, speed, dt, chord)
    h = dt / substeps
    for k in range(steps):
        out[k] = x[rows]
        if k == steps - 1:
            break
        applied[steer] = torque if k < pulse_steps else 0.0
        for _ in range(substeps):
            k1 = _derivative(system, x, speed, applied, chord, k4)
            k2 = _derivative(system, x + 0.5 * h * k1, speed, applied, chord, k1)
            k3 = _derivative(system, x + 0.5 * h * k2, speed, applied, chord, k2)
            k4 = _derivative(system, x + h * k3, speed, applied, chord, k3)
            x = x + h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4)
    return PulseResponse(np.arange(steps) * dt, out, names, torque, pulse_steps * dt, speed)
