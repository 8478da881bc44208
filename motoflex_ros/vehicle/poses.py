"""Poses of the vehicle's bodies along a response, in a world frame ('odom'-like, REP-103).

A response of the linearized vehicle (e.g. the steer-torque pulse of
:mod:`motoflex_ros.vehicle.steer_pulse`) gives the states x(t): the non-cyclic coordinates (roll,
joint angles), the independent speeds and tyre states. The cyclic coordinates are not states.
Their rates are: on tyres the lateral velocity v_y and the yaw rate r of the base are states;
with knife-edge wheels they are dependent speeds that the rolling constraints give from x (for
the Whipple bicycle r = (v delta + c delta') cos(lambda) / w, steer delta, trail c, wheelbase w,
steer axis tilt lambda). The base's planar pose follows by integration over time t [s]:

    psi' = r,    X' = v cos(psi) - v_y sin(psi),    Y' = v sin(psi) + v_y cos(psi),

v the forward speed [m/s] (x and y of the base are speeds in the heading frame), X, Y [m] the
base origin in the world frame (x forward along the initial heading, y left, z up) and psi [rad]
the heading. Every body's pose is the engine's kinematics (:func:`~motoflex_ros.vehicle.
kinematics.frame_states`) at the coordinates with the cyclic ones at zero, carried by the
planar pose: R_world = R_z(psi) R, t_world = R_z(psi) t + (X, Y, 0).
"""
from dataclasses import dataclass

import numpy as np
from scipy.integrate import cumulative_trapezoid

from motoflex_ros.vehicle.dynamics import dependent_speeds, positions
from motoflex_ros.vehicle.kinematics import frame_states

__all__ = ["WorldPoses", "response_coordinates", "base_rates", "planar_path", "frame_poses",
           "world_poses"]


@dataclass(frozen=True)
class WorldPoses:
    """Poses along a response: time [s] (n_t,), heading psi [rad] (n_t,), base origin X, Y [m]
    (n_t, 2), coordinates q (n_t, n_coords) with the cyclic ones at zero, and per kinematic
    frame rotations (n_t, n_frames, 3, 3) and translations [m] (n_t, n_frames, 3) in the world
    frame (x = R x_ref + t)."""

    time: np.ndarray
    heading: np.ndarray
    position: np.ndarray
    coordinates: np.ndarray
    rotations: np.ndarray
    translations: np.ndarray


def response_coordinates(system, states):
    """Coordinates q (n_t, n_coords) of state rows (n_t, n_states): the independent ones from
    the states, base height and pitch from the contact constraints, cyclic ones zero."""
    return np.array([positions(system, np.asarray(x, float)) for x in states])


def base_rates(system, states, speed, q_rows=None):
    """Lateral velocity v_y [m/s] and yaw rate r [rad/s] of the base per state row (n_t,).

    States when the wheels run on tyres; otherwise solved from the rolling constraints
    G u = 0 at the state (knife-edge wheels), with forward speed ``speed`` [m/s]. ``q_rows``:
    the coordinates of the rows if known (:func:`response_coordinates`).
    """
    index = system.tree.index
    nq, nu = len(system.indep_pos), len(system.indep_speed)
    states = np.asarray(states, float)
    base = [index("y"), index("yaw")]
    if all(k in system.indep_speed for k in base):   # tyres: both are states
        columns = [nq + list(system.indep_speed).index(k) for k in base]
        return states[:, columns[0]], states[:, columns[1]]
    q_rows = response_coordinates(system, states) if q_rows is None else q_rows
    rates = []
    for x, q in zip(states, q_rows):
        known = np.zeros(len(system.tree.coordinates))
        known[0] = speed
        known[list(system.indep_speed)] = x[nq:nq + nu]
        u = dependent_speeds(system, q, known)
        rates.append((u[index("y")], u[index("yaw")]))
    rates = np.array(rates).reshape(-1, 2)
    return rates[:, 0], rates[:, 1]


def planar_path(time, speed, lateral_velocity, yaw_rate):
    """Heading psi [rad] and base origin (X, Y) [m] (n_t, 2) by integrating the module
    docstring's equations from psi = X = Y = 0 (trapezoidal rule; exact for the heading when
    the yaw rate [rad/s] is linear between samples). ``speed`` [m/s] forward, scalar or
    (n_t,); ``lateral_velocity`` [m/s] in the heading frame."""
    time = np.asarray(time, float)
    heading = cumulative_trapezoid(yaw_rate, time, initial=0.0)
    cos, sin = np.cos(heading), np.sin(heading)
    vx = speed * cos - np.asarray(lateral_velocity) * sin
    vy = speed * sin + np.asarray(lateral_velocity) * cos
    position = np.column_stack([cumulative_trapezoid(vx, time, initial=0.0),
                                cumulative_trapezoid(vy, time, initial=0.0)])
    return heading, position


def frame_poses(tree, q_rows):
    """Rotations (n_t, n_frames, 3, 3) and translations [m] (n_t, n_frames, 3) of every
    kinematic frame at each coordinate row (n_t, n_coords), in the vehicle's own frame."""
    zero = np.zeros(len(tree.coordinates))
    states = [frame_states(tree, np.asarray(q, float), zero) for q in q_rows]
    return (np.array([[f.R for f in s] for s in states]),
            np.array([[f.t for f in s] for s in states]))


def world_poses(lin, time, states, speed, rows=None):
    """WorldPoses of a response: ``states`` (n_t, n_states) in ``lin.state_names`` order at
    ``time`` [s], forward speed ``speed`` [m/s] (module docstring). ``rows``: indices of the
    samples whose poses are wanted (default: all); the path is integrated over every sample
    either way, so a pose at a row is the same as in the full result."""
    system = lin.system
    states = np.asarray(states, float)
    every = rows is None
    rows = np.arange(len(states)) if every else np.asarray(rows, int)
    q = response_coordinates(system, states[rows])
    heading, position = planar_path(time, speed,
                                    *base_rates(system, states, speed, q if every else None))
    heading, position = heading[rows], position[rows]
    rotations, translations = frame_poses(system.tree, q)
    cos, sin = np.cos(heading), np.sin(heading)
    yaw = np.zeros((len(heading), 3, 3))
    yaw[:, 0, 0], yaw[:, 0, 1], yaw[:, 1, 0], yaw[:, 1, 1], yaw[:, 2, 2] = cos, -sin, sin, cos, 1
    offset = np.column_stack([position, np.zeros(len(heading))])
    return WorldPoses(np.asarray(time, float)[rows], heading, position, q,
                      np.einsum("tij,tfjk->tfik", yaw, rotations),
                      np.einsum("tij,tfj->tfi", yaw, translations) + offset[:, None, :])
