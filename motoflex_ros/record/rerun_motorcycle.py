"""The motorcycle in the recording: bodies, joint axes, weave and wobble, road test, written
from a :class:`~motoflex_ros.vehicle.animation.MotorcycleMotion` (the core computes the motion;
this module only draws it).

Bodies are drawn as their equivalent-inertia ellipsoids (the uniform solid ellipsoid with the
body's mass and principal moments: a_i^2 = 5 (I_j + I_k - I_i) / (2 m)) and the wheels as
cylinders (radius, width twice the crown radius).
"""
import numpy as np
import rerun as rr
from scipy.spatial.transform import Rotation

from motoflex_ros.record import rerun_vehicle as rv
from motoflex_ros.record.rerun_log import TIMELINE
from motoflex_ros.units import ms_to_kmh

__all__ = ["log_motorcycle", "ellipsoid_half_sizes", "MIN_HALF_SIZE"]

MIN_HALF_SIZE = 0.02


def ellipsoid_half_sizes(mass, principal_moments):
    """Semi-axes [m] of the uniform solid ellipsoid of ``mass`` [kg] and principal moments
    [kg m^2]: a_i = sqrt(5 (I_j + I_k - I_i) / (2 m)), at least :data:`MIN_HALF_SIZE`."""
    i = np.asarray(principal_moments, float)
    squares = 5.0 * (i.sum() - 2.0 * i) / (2.0 * mass)
    return np.maximum(np.sqrt(np.maximum(squares, 0.0)), MIN_HALF_SIZE)


def _shapes(model, tree):
    """[(entity name, frame index, archetype)] of bodies with mass and of the wheels."""
    shapes = []
    for body in model.bodies:
        if body.mass <= 0:
            continue
        moments, axes = np.linalg.eigh(body.inertia)
        if np.linalg.det(axes) < 0:
            axes[:, 0] *= -1
        shapes.append((body.name, tree.body_frames[body.name], rr.Ellipsoids3D(
            centers=[body.com], half_sizes=[ellipsoid_half_sizes(body.mass, moments)],
            quaternions=[Rotation.from_matrix(axes).as_quat()], colors=(170, 170, 185),
            fill_mode="solid")))
    for wheel, frame in zip(model.wheels, tree.wheel_frames):
        shapes.append((f"{wheel.name}_wheel", frame, rr.Cylinders3D(
            lengths=[2 * wheel.crown_radius], radii=[wheel.radius], centers=[wheel.centre],
            rotation_axis_angles=[rr.RotationAxisAngle([1, 0, 0], degrees=90)],
            colors=(60, 60, 60), fill_mode="solid")))
    return shapes


def _log_animated(rec, base, shapes, rotations, translations, timeline, times):
    """Shapes moved by their frames' poses (n_t, n_frames, ...) on ``timeline`` at ``times``."""
    index = (rr.TimeColumn(timeline, sequence=times) if timeline != TIMELINE
             else rr.TimeColumn(TIMELINE, duration=times))
    for name, frame, archetype in shapes:
        rec.log(f"{base}/{name}/shape", archetype, static=True)
        rec.send_columns(f"{base}/{name}", indexes=[index], columns=rr.Transform3D.columns(
            translation=translations[:, frame], mat3x3=rotations[:, frame]))


def _log_mode(rec, shapes, mode, offset):
    base = f"/vehicle/modes/{mode.name}"
    lam = mode.eigenvalue
    rec.log(base, rr.Transform3D(translation=offset), static=True)
    rec.log(f"{base}/description", rr.TextDocument(
        f"{mode.name} at {ms_to_kmh(mode.speed):.0f} km/h: lambda = {lam.real:.3f} "
        f"{lam.imag:+.3f}i 1/s ({lam.imag / (2 * np.pi):.2f} Hz); exaggerated so the largest "
        f"angle is {mode.amplitude_rad} rad; two cycles on the {rv.MODE_TIMELINE} timeline."),
        static=True)
    _log_animated(rec, base, shapes, mode.rotations, mode.translations, rv.MODE_TIMELINE,
                  np.arange(len(mode.rotations)))


def _log_road_test(rec, shapes, road):
    rv.log_joint_series(rec, list(road.joints), road.time, road.joint_series)
    rec.log("/vehicle/road_test/description", rr.TextDocument(
        f"Steer-torque pulse {road.torque:g} N m for {road.duration:g} s at "
        f"{ms_to_kmh(road.speed):.0f} km/h; bodies in the world frame (x along the initial "
        f"heading, path and heading integrated), response scaled x{road.factor:.3g} (a larger "
        f"pulse); joint series true size."), static=True)
    _log_animated(rec, "/vehicle/road_test", shapes, road.rotations, road.translations,
                  TIMELINE, road.time)
    return len(road.time)


def log_motorcycle(rec, motion, joint_axes=True):
    """Log a MotorcycleMotion: bodies, joint axes (``joint_axes`` False leaves the revolute
    joints' axes out: a bag's markers draw them), each mode beside the others, the road test
    (when ``motion.road``). Returns the number of road-test samples (0 without one)."""
    shapes = _shapes(motion.model, motion.tree)
    for joint in motion.model.joints if joint_axes else ():
        if joint.kind == "revolute":
            rv.log_joint_axis(rec, joint.name, joint.point, joint.axis)
    for k, mode in enumerate(motion.modes.values()):
        _log_mode(rec, shapes, mode, (0.0, 2.0 * (k + 1), 0.0))
    return _log_road_test(rec, shapes, motion.road) if motion.road is not None else 0
