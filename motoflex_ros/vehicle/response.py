"""Virtual road test: response of the linearized vehicle to a short steer-torque pulse, and
weave/wobble identified back from it by the matrix-pencil method.

Exact discretisation (zero-order hold, exact for a pulse that starts and ends on samples):
x[k+1] = Phi x[k] + Gamma u[k] with [[Phi, Gamma], [0, I]] = expm([[A, B], [0, 0]] dt), where
A = E^-1 A(v) and B = E^-1 b, b the input column of a joint torque (1 N m on the joint).

Matrix pencil (Hua & Sarkar, IEEE Trans. ASSP 38(5), 1990): the free response after the pulse,
y[k] = sum_i r_i z_i^k, is arranged in a (block) Hankel matrix Y (one block per output, pencil
parameter L = N/2); with Y = U S V^H truncated to its M significant singular values, the poles
are z_i = eig(pinv(V1) V2), V1/V2 the rows of V without the last/first one; s_i = ln(z_i)/dt.
"""
from dataclasses import dataclass

import numpy as np
import scipy.linalg

from motoflex_ros.errors import ModelError
from motoflex_ros.vehicle.dynamics import residual

__all__ = ["PulseResponse", "joint_input", "steer_pulse_response", "matrix_pencil_poles"]


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


def steer_pulse_response(lin, speed, torque=20.0, duration=0.05, t_end=4.0, dt=0.005,
                         outputs=None):
    """Response to a steer-torque pulse of ``torque`` [N m] for ``duration`` [s] at ``speed``
    [m/s], sampled every dt [s] to t_end [s]. outputs: state names (default: steer, roll and
    yaw rates)."""
    joint = lin.system.model.roles.get("steer")
    if joint is None:
        raise ModelError(f"{lin.system.model.source}: no 'steer' role to apply the pulse to")
    names = tuple(outputs or (joint, "roll_rate", "yaw_rate"))
    rows = [lin.state_names.index(name) for name in names]
    E, A = lin.pencil([speed])
    a, b = np.linalg.solve(E[0], A[0]), np.linalg.solve(E[0], joint_input(lin, joint))
    phi, gamma = _discretise(a, b, dt)
    steps = int(round(t_end / dt)) + 1
    pulse_steps = int(round(duration / dt))
    x = np.zeros(a.shape[0])
    out = np.empty((steps, len(rows)))
    for k in range(steps):
        out[k] = x[rows]
        x = phi @ x + gamma * (torque if k < pulse_steps else 0.0)
    return PulseResponse(np.arange(steps) * dt, out, names, torque, pulse_steps * dt, speed)


def matrix_pencil_poles(samples, dt, order=None, rtol=1e-9):
    """Continuous-time poles [1/s] of free-response samples (k, m) by the matrix pencil.

    order: model order M (default: the number of singular values above rtol * largest).
    """
    samples = np.atleast_2d(np.asarray(samples, float).T).T
    count = samples.shape[0]
    pencil = count // 2
    blocks = [scipy.linalg.hankel(y[:count - pencil], y[count - pencil - 1:])
              for y in samples.T]
    scale = np.array([np.max(np.abs(y)) or 1.0 for y in samples.T])
    hankel = np.vstack([blk / s for blk, s in zip(blocks, scale)])
    _, sv, vh = np.linalg.svd(hankel, full_matrices=False)
    if order is None:
        order = int(np.sum(sv > rtol * sv[0]))
    v = vh[:order].conj().T
    z = np.linalg.eigvals(np.linalg.pinv(v[:-1]) @ v[1:])
    return np.log(z.astype(complex)) / dt
