"""The motorcycle in motion for viewers: weave and wobble mode shapes and the road test, as body
poses over time (the physics a rerun recording draws; record/ only writes what this returns).

Poses come from the engine's own kinematics (:func:`motoflex_ros.vehicle.poses.frame_poses`) at
coordinates q:

- modes: q(phi) = Re(s q_c e^{i phi}), q_c the eigenvector's coordinates (coordinates that are
  states directly; cyclic ones, y and yaw, from their rates as q = q'/lambda), scaled by s so
  the largest joint or attitude angle is :data:`MODE_AMPLITUDE_RAD` [rad].
- road test: the steer-torque pulse response (:func:`~motoflex_ros.vehicle.steer_pulse.
  steer_pulse_response`) scaled so the largest angle is :data:`ROAD_AMPLITUDE_RAD` (a larger
  pulse, the response being linear), in the world frame with the path and heading integrated
  by the core (:func:`motoflex_ros.vehicle.poses.world_poses`), as the vehicle_simulator node
  publishes it.
"""
from dataclasses import dataclass

import numpy as np

from motoflex_ros.units import kmh_to_ms
from motoflex_ros.vehicle.linearize import linearize
from motoflex_ros.vehicle.mode_names import STUDIED_MODES
from motoflex_ros.vehicle.modes import eigen_decomposition, modal_sweep
from motoflex_ros.vehicle.poses import frame_poses, world_poses
from motoflex_ros.vehicle.steer_pulse import steer_pulse_response

__all__ = ["ModeMotion", "RoadTest", "MotorcycleMotion", "motorcycle_motion",
           "mode_coordinates", "mode_rows", "road_test", "body_rows",
           "MODE_AMPLITUDE_RAD",
           "ROAD_AMPLITUDE_RAD", "MODE_FRAMES_PER_CYCLE", "MODE_CYCLES", "DEFAULT_SPEED_MPS"]

MODE_AMPLITUDE_RAD = 0.15
MODE_FRAMES_PER_CYCLE = 24
MODE_CYCLES = 2
ROAD_AMPLITUDE_RAD = 0.15
DEFAULT_SPEED_MPS = float(kmh_to_ms(100.0))  # road test and modes at 100 km/h [m/s]


@dataclass(frozen=True)
class ModeMotion:
    """One mode animated: ``eigenvalue`` [1/s] at ``speed`` [m/s]; ``rotations`` (n_frames,
    n_body_frames, 3, 3) and ``translations`` (n_frames, n_body_frames, 3) [m] per animation
    frame, exaggerated so that the largest angle is ``amplitude_rad``."""

    name: str
    speed: float
    eigenvalue: complex
    rotations: np.ndarray
    translations: np.ndarray
    amplitude_rad: float = MODE_AMPLITUDE_RAD


@dataclass(frozen=True)
class RoadTest:
    """The steer-torque pulse response: ``time`` [s], the joints' series (true size, ``joints``
    names, ``joint_series`` (n_t, n_joints) [rad or m]), body poses in the world frame scaled by
    ``factor`` (``rotations``, ``translations`` as in ModeMotion, at the samples ``rows`` of
    ``time``), the pulse's ``torque`` [N m] and ``duration`` [s] at ``speed`` [m/s]; ``states``
    (n_t, n_states) the whole response, true size, in ``state_names`` order."""

    speed: float
    time: np.ndarray
    joints: tuple
    joint_series: np.ndarray
    rotations: np.ndarray
    translations: np.ndarray
    factor: float
    torque: float
    duration: float
    rows: np.ndarray = None
    state_names: tuple = ()
    states: np.ndarray = None

    def efforts(self, joints, steer):
        """Applied joint torques (n_t, len(joints)) [N m]: the pulse on ``steer`` while it
        lasts, zero elsewhere."""
        out = np.zeros((len(self.time), len(joints)))
        if steer in joints:
            out[:, list(joints).index(steer)] = np.where(self.time < self.duration,
                                                         self.torque, 0.0)
        return out


@dataclass(frozen=True)
class MotorcycleMotion:
    """What a viewer draws of a motorcycle: its ``model`` (bodies, joints, wheels), the compiled
    ``tree`` (the frame index of every body and wheel), ``modes`` {name: ModeMotion} and the
    ``road`` test (or None)."""

    model: object
    tree: object
    modes: dict
    road: object


def _coordinate_map(lin, values):
    """Coordinates q (n,) from {state name: value} (states that are coordinates)."""
    names = [c.name for c in lin.system.tree.coordinates]
    q = [np.zeros_like(next(iter(values.values()))) for _ in names]
    for state, value in values.items():
        if state in names:
            q[names.index(state)] = value
    return q


def mode_coordinates(lin, speed, eigenvalue):
    """Complex coordinates q_c (n,) of the eigenvector nearest ``eigenvalue`` at ``speed``."""
    values, vectors = eigen_decomposition(lin, [speed])
    index = int(np.nanargmin(np.abs(values[0] - eigenvalue)))
    lam, vector = values[0][index], vectors[0][:, index]
    states = dict(zip(lin.state_names, vector))
    for name in ("y", "yaw"):
        if name not in states and f"{name}_rate" in states:
            states[name] = states[f"{name}_rate"] / lam
    return np.array(_coordinate_map(lin, states), complex), lam


def _angle_indices(tree):
    return [k for k, c in enumerate(tree.coordinates)
            if c.kind == "revolute" and c.group != "spin" and c.name != "pitch"]


def mode_rows(lin, speed, eigenvalue):
    """Coordinates q (n_frames, n) of the animation of a mode, and its eigenvalue [1/s].

    q(phi) = Re(s q_c e^{i phi}) over :data:`MODE_CYCLES` cycles; s scales and turns q_c so the
    largest angle is :data:`MODE_AMPLITUDE_RAD` and real at phi = 0.
    """
    q_c, lam = mode_coordinates(lin, speed, eigenvalue)
    angles = _angle_indices(lin.system.tree)
    biggest = angles[int(np.argmax(np.abs(q_c[angles])))]
    q_c = q_c * MODE_AMPLITUDE_RAD * np.exp(-1j * np.angle(q_c[biggest])) / abs(q_c[biggest])
    phase = 2 * np.pi * np.arange(MODE_FRAMES_PER_CYCLE * MODE_CYCLES) / MODE_FRAMES_PER_CYCLE
    return (q_c[None, :] * np.exp(1j * phase)[:, None]).real, lam


def body_rows(time, rate_hz):
    """Indices of the response samples (``time`` [s], uniform) whose poses are kept at about
    ``rate_hz`` [Hz]: every n-th sample, n = round(1 / (rate_hz dt)) >= 1, from the first.

    >>> body_rows(np.arange(0.0, 0.05, 0.005), 50.0).tolist()
    [0, 4, 8]
    """
    dt = (time[-1] - time[0]) / (len(time) - 1) if len(time) > 1 else 1.0
    return np.arange(0, len(time), max(1, int(round(1.0 / (rate_hz * dt)))))


def road_test(lin, speed, amplitude_rad=ROAD_AMPLITUDE_RAD, pose_rate_hz=None):
    """RoadTest: the steer-pulse response at ``speed`` [m/s], poses scaled so that the largest
    angle is ``amplitude_rad`` [rad] (None: true size, as the vehicle_simulator node publishes
    them), at about ``pose_rate_hz`` [Hz] (:func:`body_rows`; default every sample: the path
    is integrated over every sample either way)."""
    names = tuple(lin.state_names)
    pulse = steer_pulse_response(lin, speed, outputs=names)
    n_angles = len(lin.system.indep_pos)          # roll and the joint angles
    factor = 1.0 if amplitude_rad is None else \
        amplitude_rad / max(np.abs(pulse.outputs[:, :n_angles]).max(), 1e-12)
    joints = tuple(n for n in names if n in {c.name for c in lin.system.tree.coordinates})
    series = np.column_stack([pulse.outputs[:, names.index(n)] for n in joints])
    rows = None if pose_rate_hz is None else body_rows(pulse.time, pose_rate_hz)
    poses = world_poses(lin, pulse.time, pulse.outputs if amplitude_rad is None
                        else factor * pulse.outputs, speed, rows)
    return RoadTest(speed, pulse.time, joints, series, poses.rotations, poses.translations,
                    factor, pulse.torque, pulse.duration,
                    np.arange(len(pulse.time)) if rows is None else np.asarray(rows, int),
                    names, pulse.outputs)


def motorcycle_motion(model, speed_mps=DEFAULT_SPEED_MPS, modes=None, road=True):
    """MotorcycleMotion of the VehicleModel ``model`` at ``speed_mps`` [m/s].

    ``modes``: {name: eigenvalue at speed_mps [1/s]}; by default weave and wobble from the
    engine's own modal sweep (a mode not found there is left out). ``road``: with the road test.
    """
    lin = linearize(model)
    if modes is None:
        sweep = modal_sweep(lin, np.array([speed_mps]))
        modes = {m: sweep.modes[m][0] for m in STUDIED_MODES}
    animated = {}
    for name, eigenvalue in modes.items():
        if np.isfinite(eigenvalue):
            rows, lam = mode_rows(lin, speed_mps, eigenvalue)
            rotations, translations = frame_poses(lin.system.tree, rows)
            animated[name] = ModeMotion(name, speed_mps, lam, rotations, translations)
    return MotorcycleMotion(model, lin.system.tree, animated,
                            road_test(lin, speed_mps) if road else None)
