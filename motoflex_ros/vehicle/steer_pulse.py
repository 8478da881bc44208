"""Virtual road test: response of the linearized vehicle to a short steer-torque pulse, and
weave/wobble identified back from it by the matrix-pencil method.

Exact discretisation (zero-order hold, exact for a pulse that starts and ends on samples):
x[k+1] = Phi x[k] + Gamma u[k] with [[Phi, Gamma], [0, I]] = expm([[A, B], [0, 0]] dt), where
A = E^-1 A(v) and B = E^-1 b, b the input column of a joint torque (1 N m on the joint); a
singular E (massless bodies) is first reduced to its regular part (index 1).

The free response after the pulse, y[k] = sum_i r_i z_i^k, gives weave and wobble back by the
matrix pencil (:func:`motoflex_ros.identify.matrix_pencil.matrix_pencil_poles` on the outputs
scaled by :func:`~motoflex_ros.identify.matrix_pencil.unit_peak`, pencil parameter L = N/2).
"""
from dataclasses import dataclass

import numpy as np
import scipy.linalg

from motoflex_ros.errors import ModelError
from motoflex_ros.vehicle.dynamics import residual

__all__ = ["PulseResponse", "joint_input", "pulse_output_names", "regular_part",
           "steer_pulse_response"]


@dataclass(frozen=True)
class PulseResponse:
    """time [s] (k,), outputs (k, m) named by output_names (state units), the pulse torque
    [N m] and duration [s], the speed [m/s]."""

    time: np.ndarray
    outputs: np.ndarray
    output_names: tuple
    torque: float
    duration: float
    speed: float


def joint_input(lin, joint):
    """Input column b [1/(N m) in residual units] of a unit torque on ``joint``: E x' = A x + b T.

    b = -dR/dT (the residual is linear in the applied torque); T acts between the joint's
    parent and child bodies about the joint axis.
    """
    system = lin.system
    k = system.tree.index(joint)
    applied = np.zeros(len(system.tree.coordinates))
    applied[k] = 1.0
    zero = np.zeros(system.n_states)
    speed = 1.0   # the input column does not depend on speed (partial velocities at rest)
    return residual(system, zero, zero, speed) - residual(system, zero, zero, speed, applied)


def _discretise(a, b, dt):
    n = a.shape[0]
    block = np.zeros((n + 1, n + 1))
    block[:n, :n], block[:n, n] = a * dt, b * dt
    exp = scipy.linalg.expm(block)
    return exp[:n, :n], exp[:n, n]


def regular_part(E, A, b, rtol=1e-10):
    """Ordinary state-space form of an index-1 descriptor system E x' = A x + b u.

    With E = U diag(s, 0) V^T (SVD) and z = V^T x split into (z1, z2), the rows of E's null
    space are algebraic: z2 = -A22^-1 (A21 z1 + b2 u) (massless bodies). Returns (a, bz, P, d)
    with z1' = a z1 + bz u and x = P z1 + d u; a regular E gives a = E^-1 A, bz = E^-1 b,
    P = I, d = 0.
    """
    U, s, Vt = np.linalg.svd(E)
    r = int(np.sum(s > rtol * s[0]))
    At, bt = U.T @ A @ Vt.T, U.T @ b
    V1, V2 = Vt[:r].T, Vt[r:].T
    if r == E.shape[0]:
        n = E.shape[0]
        return np.linalg.solve(E, A), np.linalg.solve(E, b), np.eye(n), np.zeros(n)
    try:
        solve22 = np.linalg.solve(At[r:, r:], np.column_stack([At[r:, :r], bt[r:]]))
    except np.linalg.LinAlgError:
        raise ModelError("descriptor system of index > 1 (A22 singular): not supported") from None
    k_z, k_u = -solve22[:, :r], -solve22[:, r]
    a = (At[:r, :r] + At[:r, r:] @ k_z) / s[:r, None]
    bz = (bt[:r] + At[:r, r:] @ k_u) / s[:r]
    return a, bz, V1 + V2 @ k_z, V2 @ k_u


def pulse_output_names(system, joint, outputs):
    """The requested state names of the VehicleSystem ``system``, or the default ones (the
    steer angle ``joint``, roll rate and, where it is a state, yaw rate); ModelError naming an
    unknown one."""
    default = [joint, "roll_rate"] + (["yaw_rate"] if "yaw_rate" in system.state_names else [])
    names = tuple(outputs or default)
    unknown = [n for n in names if n not in system.state_names]
    if unknown:
        hint = (" (with knife-edge wheels the lateral and yaw rates follow from the rolling "
                "constraints: they are not states)"
                if unknown[0] in ("yaw_rate", "y_rate") else "")
        raise ModelError(f"{system.model.source}: no state {unknown[0]!r} to output{hint}; "
                         f"states: {', '.join(system.state_names)}")
    return names


def steer_pulse_response(lin, speed, torque=20.0, duration=0.05, t_end=4.0, dt=0.005,
                         outputs=None):
    """Response of the linearized vehicle to a steer-torque pulse (module docstring).

    Parameters
    ----------
    lin : LinearVehicle
        The linearized vehicle; its model's 'steer' role names the joint the torque acts on.
    speed : float
        Forward speed [m/s].
    torque, duration : float
        Pulse torque [N m] on the steer joint and its duration [s].
    t_end, dt : float
        End time and sample period [s].
    outputs : sequence of str, optional
        State names to return (``lin.state_names``). Default: the steer angle [rad], the roll
        rate [rad/s] and, only where it is a state (tyred wheels), the yaw rate [rad/s]; with
        knife-edge wheels yaw rate is not a state and asking for it is a ModelError.

    Returns
    -------
    PulseResponse
        Sampled outputs (state units); a singular E (massless bodies) is reduced by
        :func:`regular_part`.

    """
    joint = lin.system.model.roles.get("steer")
    if joint is None:
        raise ModelError(f"{lin.system.model.source}: no 'steer' role to apply the pulse to")
    names = pulse_output_names(lin.system, joint, outputs)
    rows = [lin.state_names.index(name) for name in names]
    E, A = lin.pencil([speed])
    a, b, to_x, feed = regular_part(E[0], A[0], joint_input(lin, joint))
    phi, gamma = _discretise(a, b, dt)
    steps = int(round(t_end / dt)) + 1
    pulse_steps = int(round(duration / dt))
    z = np.zeros(a.shape[0])
    out = np.empty((steps, len(rows)))
    for k in range(steps):
        u = torque if k < pulse_steps else 0.0
        out[k] = to_x[rows] @ z + feed[rows] * u
        z = phi @ z + gamma * u
    return PulseResponse(np.arange(steps) * dt, out, names, torque, pulse_steps * dt, speed)

