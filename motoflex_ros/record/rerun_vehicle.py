"""Rerun recording of the motorcycle: bodies, identified joint axes, road test, modes, eigenvalues.

Plain numbers in, entities out (see :mod:`.rerun_log` for the bench). Vehicle frame REP-103
(x forward, y left, z up), origin on the ground below the rear wheel centre. Quaternions are
(x, y, z, w). Entity paths:

==========================================  ==================================================
path                                        content
==========================================  ==================================================
/vehicle/road_test/<body>                   body pose (Transform3D) over ``sim_time`` and its
                                            shape (box, cylinder or capsule) in body axes
/vehicle/road_test/joints/<joint>           joint coordinate [m or rad] (Scalars) over time
/vehicle/joint_axes/<name>                  identified joint axis (LineStrips3D) and joint
                                            point (Points3D), static
/vehicle/modes/<mode>/<body>                mode shape animated on the ``mode_frame`` timeline
/vehicle/modes/<mode>/description           TextDocument: speed, eigenvalue, exaggeration
/vehicle/eigenvalues/<mode>/real_part       Re(lambda) [1/s] against ``speed_kmh``
/vehicle/eigenvalues/<mode>/frequency_hz    Im(lambda)/(2 pi) [Hz] against ``speed_kmh``
/vehicle/eigenvalues/all/real_part, ...     every eigenvalue (points) against ``speed_kmh``
/vehicle/stability/<mode>/real_part         Re(lambda) [1/s] as bars over speed [km/h],
                                            static (any timeline shows it)
/vehicle/stability/<mode>/frequency_hz      frequency [Hz] as bars over speed [km/h]
==========================================  ==================================================
"""
from dataclasses import dataclass

import numpy as np
import rerun as rr
from scipy.spatial.transform import Rotation

from motoflex_ros.record.rerun_log import TIMELINE
from motoflex_ros.units import ms_to_kmh

__all__ = ["BodyShape", "log_body_shapes", "log_body_poses", "log_joint_series",
           "log_joint_axis", "log_eigenvalues", "log_mode_animation", "mode_frames",
           "SPEED_TIMELINE", "MODE_TIMELINE", "speed_kmh_index", "log_speed_bars",
           "STABILITY_QUANTITIES", "MODE_COLORS"]

SPEED_TIMELINE = "speed_kmh"
MODE_TIMELINE = "mode_frame"
MODE_COLORS = {"weave": (40, 110, 255), "wobble": (220, 50, 50), "capsize": (120, 120, 120)}


@dataclass(frozen=True)
class BodyShape:
    """Drawing of one body in its own axes: ``kind`` 'box' (half_size (3,) [m]), 'cylinder'
    (radius, width along y [m], for wheels) or 'capsule' (radius, length along z [m])."""

    name: str
    kind: str
    size: tuple
    color: tuple = (170, 170, 180)


def _shape_archetype(shape):
    if shape.kind == "box":
        return rr.Boxes3D(half_sizes=[shape.size], colors=shape.color, fill_mode="solid")
    if shape.kind == "cylinder":
        radius, width = shape.size
        return rr.Cylinders3D(lengths=[width], radii=[radius], colors=shape.color,
                              rotation_axis_angles=[rr.RotationAxisAngle([1, 0, 0], degrees=90)],
                              fill_mode="solid")
    if shape.kind == "capsule":
        radius, length = shape.size
        return rr.Capsules3D(lengths=[length], radii=[radius], colors=shape.color,
                             translations=[[0.0, 0.0, -length / 2]])
    raise ValueError(f"body {shape.name}: unknown shape kind '{shape.kind}'")


def log_body_shapes(rec, base, shapes, timeline=None):
    """Shapes of the bodies under ``base`` (static, or at index 0 of a sequence timeline)."""
    if timeline is not None:
        rec.set_time(timeline, sequence=0)
    for shape in shapes:
        rec.log(f"{base}/{shape.name}/shape", _shape_archetype(shape), static=timeline is None)


def log_body_poses(rec, base, names, times, positions, quaternions):
    """Poses of bodies over ``sim_time``: positions (n_t, n_b, 3) [m], quaternions (n_t, n_b, 4).

    Returns the number of poses logged per body.
    """
    times = np.asarray(times, float)
    positions = np.asarray(positions, float)
    quaternions = np.asarray(quaternions, float)
    for j, name in enumerate(names):
        rec.send_columns(f"{base}/{name}",
                         indexes=[rr.TimeColumn(TIMELINE, duration=times)],
                         columns=rr.Transform3D.columns(translation=positions[:, j],
                                                        quaternion=quaternions[:, j]))
    return len(times)


def log_joint_series(rec, names, times, positions):
    """Joint coordinates (n_t, n_joints) [m or rad] of the road test as Scalars."""
    times = np.asarray(times, float)
    positions = np.asarray(positions, float).reshape(len(times), -1)
    for j, name in enumerate(names):
        rec.send_columns(f"/vehicle/road_test/joints/{name}",
                         indexes=[rr.TimeColumn(TIMELINE, duration=times)],
                         columns=rr.Scalars.columns(scalars=positions[:, j]))
    return len(times)


def log_joint_axis(rec, name, point, direction, half_length=0.25, color=(30, 170, 60)):
    """An identified joint axis of the lumped motorcycle in the vehicle frame (static).

    ``point`` [m] on the axis (the revolute joint), ``direction`` its direction (normalised
    here); drawn ``half_length`` [m] either side of the point.
    """
    point = np.asarray(point, float)
    direction = np.asarray(direction, float)
    direction = direction / np.linalg.norm(direction)
    strip = [point - half_length * direction, point + half_length * direction]
    path = f"/vehicle/joint_axes/{name}"
    rec.log(path, rr.LineStrips3D([strip], colors=color, radii=0.006, labels=[name],
                               show_labels=False),
            static=True)
    rec.log(f"{path}/joint", rr.Points3D([point], colors=color, radii=0.02), static=True)


def speed_kmh_index(speeds_mps):
    """Integer km/h of each speed [m/s] (the ``speed_kmh`` sequence); distinct or ValueError."""
    kmh = np.round(ms_to_kmh(speeds_mps)).astype(int)
    if len(np.unique(kmh)) != len(kmh):
        raise ValueError("speeds closer than 1 km/h cannot share the speed_kmh timeline")
    return kmh


def _speed_series(rec, path, kmh, values, name, points=False, color=None):
    values = np.asarray(values, float).reshape(len(kmh), -1)
    style = rr.SeriesPoints(names=[name] * values.shape[1], marker_sizes=[2.0] * values.shape[1]
                            ) if points else rr.SeriesLines(
                                names=[name], colors=None if color is None else [color])
    rec.log(path, style, static=True)
    rec.send_columns(path, indexes=[rr.TimeColumn(SPEED_TIMELINE, sequence=kmh)],
                     columns=rr.Scalars.columns(scalars=values))


def log_eigenvalues(rec, speeds_mps, eigenvalues, tracked):
    """Eigenvalues against speed: every eigenvalue with Im > 0 as points, tracked modes as lines.

    ``eigenvalues`` (n_speeds, n) complex [1/s], or None when only the tracked modes are known
    (no ``all`` series); ``tracked`` maps a mode name (weave, wobble) to its eigenvalue per
    speed (n_speeds,) complex (NaN where not found). Returns the number of speeds.
    """
    kmh = speed_kmh_index(speeds_mps)
    if eigenvalues is not None:
        lam = np.asarray(eigenvalues, complex).reshape(len(kmh), -1)
        oscillating = np.where(lam.imag > 1e-9, lam, np.nan)
        _speed_series(rec, "/vehicle/eigenvalues/all/real_part", kmh, oscillating.real,
                      "Re(lambda) [1/s]", points=True)
        _speed_series(rec, "/vehicle/eigenvalues/all/frequency_hz", kmh,
                      oscillating.imag / (2 * np.pi), "f [Hz]", points=True)
    for mode, values in tracked.items():
        values = np.asarray(values, complex)
        color = MODE_COLORS.get(mode)
        _speed_series(rec, f"/vehicle/eigenvalues/{mode}/real_part", kmh, values.real,
                      f"{mode} Re(lambda) [1/s]", color=color)
        _speed_series(rec, f"/vehicle/eigenvalues/{mode}/frequency_hz", kmh,
                      values.imag / (2 * np.pi), f"{mode} f [Hz]", color=color)
        log_speed_bars(rec, mode, kmh, values)
    return len(kmh)


STABILITY_QUANTITIES = {"real_part": "Re [1/s]", "frequency_hz": "f [Hz]"}
"""The bar charts of /vehicle/stability/<mode>/<quantity> and how their views name them."""


def log_speed_bars(rec, mode, kmh, values):
    """A mode's real part [1/s] and frequency [Hz] as static bar charts over speed [km/h]
    (the bars' abscissa): visible on whatever timeline the viewer shows, unlike a time series
    on ``speed_kmh``. A speed where the mode was not found has no bar (0)."""
    values = np.asarray(values, complex)
    color = MODE_COLORS.get(mode, (120, 120, 120))
    for quantity, numbers in (("real_part", values.real),
                              ("frequency_hz", values.imag / (2 * np.pi))):
        rec.log(f"/vehicle/stability/{mode}/{quantity}",
                rr.BarChart(np.nan_to_num(numbers, nan=0.0), abscissa=np.asarray(kmh, float),
                            color=color), static=True)


def mode_frames(translation_shape, rotation_shape, frames_per_cycle=24, cycles=2):
    """Body motion of a mode over ``cycles`` periods: Re(shape e^{i phase}).

    ``translation_shape`` and ``rotation_shape`` (n_b, 3) complex [m, rad]; returns
    (translations (n_f, n_b, 3), rotation vectors (n_f, n_b, 3)).
    """
    phase = 2 * np.pi * np.arange(frames_per_cycle * cycles) / frames_per_cycle
    turn = np.exp(1j * phase)[:, None, None]
    return ((turn * np.asarray(translation_shape, complex)).real,
            (turn * np.asarray(rotation_shape, complex)).real)


def log_mode_animation(rec, mode, shapes, rest_positions, rest_quaternions, translation_shape,
                       rotation_shape, description, offset=(0.0, 0.0, 0.0)):
    """A vibration mode (weave, wobble) animated on the ``mode_frame`` timeline.

    The bodies start from their rest poses (n_b, 3) [m] and (n_b, 4); ``translation_shape`` and
    ``rotation_shape`` (n_b, 3) complex [m, rad] are the mode's body motions, already scaled
    (exaggerated) as ``description`` states. ``offset`` [m] places the animation beside the
    others. Returns the number of frames.
    """
    base = f"/vehicle/modes/{mode}"
    rec.log(base, rr.Transform3D(translation=np.asarray(offset, float)), static=True)
    rec.log(f"{base}/description", rr.TextDocument(description), static=True)
    colored = [BodyShape(s.name, s.kind, s.size, MODE_COLORS.get(mode, s.color)) for s in shapes]
    log_body_shapes(rec, base, colored, timeline=MODE_TIMELINE)
    moves, turns = mode_frames(translation_shape, rotation_shape)
    rest = Rotation.from_quat(np.asarray(rest_quaternions, float))
    frames = np.arange(len(moves))
    for j, shape in enumerate(shapes):
        quats = (Rotation.from_rotvec(turns[:, j]) * rest[j]).as_quat()
        rec.send_columns(f"{base}/{shape.name}",
                         indexes=[rr.TimeColumn(MODE_TIMELINE, sequence=frames)],
                         columns=rr.Transform3D.columns(
                             translation=np.asarray(rest_positions, float)[j] + moves[:, j],
                             quaternion=quats))
    return len(frames)
