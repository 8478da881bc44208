"""The motorcycle in the recording, from the vehicle engine: bodies, joint axes, road test, modes.

Bodies are drawn as their equivalent-inertia ellipsoids (the uniform solid ellipsoid with the
body's mass and principal moments: a_i^2 = 5 (I_j + I_k - I_i) / (2 m)) and the wheels as
cylinders (radius, width twice the crown radius). Poses come from the engine's own kinematics
(:func:`motoflex_ros.vehicle.kinematics.frame_states`) at coordinates q:

- modes: q(phi) = Re(s q_c e^{i phi}), q_c the eigenvector's coordinates (coordinates that are
  states directly; cyclic ones, y and yaw, from their rates as q = q'/lambda), scaled by s so
  the largest joint or attitude angle is :data:`MODE_AMPLITUDE_RAD`.
- road test: the steer-torque pulse response (:func:`~motoflex_ros.vehicle.response.
  steer_pulse_response`) scaled so the largest angle is :data:`ROAD_AMPLITUDE_RAD` (a larger
  pulse, the response being linear), in the world frame with the path and heading integrated
  by the core (:func:`motoflex_ros.vehicle.poses.world_poses`), as the vehicle_simulator node
  publishes it.
"""
import numpy as np
import rerun as rr
from scipy.spatial.transform import Rotation

from motoflex_ros.record import rerun_vehicle as rv
from motoflex_ros.record.rerun_log import TIMELINE
from motoflex_ros.units import kmh_to_ms, ms_to_kmh

__all__ = ["log_motorcycle", "vehicle_model", "ellipsoid_half_sizes", "mode_coordinates",
           "mode_rows",
           "MODE_AMPLITUDE_RAD", "ROAD_AMPLITUDE_RAD", "MODE_FRAMES_PER_CYCLE", "MODE_CYCLES"]

MODE_AMPLITUDE_RAD = 0.15
MODE_FRAMES_PER_CYCLE = 24
MODE_CYCLES = 2
ROAD_AMPLITUDE_RAD = 0.15
MIN_HALF_SIZE = 0.02
DEFAULT_SPEED_MPS = float(kmh_to_ms(100.0))  # road test and modes at 100 km/h [m/s]


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


def _coordinate_map(lin, values):
    """Coordinates q (n,) from state values: position states, and cyclic ones from rates/lam.

    ``values``: {state name: value}; for a time history, arrays; rates of cyclic coordinates
    are passed through ``integrate`` by the caller.
    """
    tree = lin.system.tree
    names = [c.name for c in tree.coordinates]
    q = [np.zeros_like(next(iter(values.values()))) for _ in names]
    for state, value in values.items():
        if state in names:
            q[names.index(state)] = value
    return q


def mode_coordinates(lin, speed, eigenvalue):
    """Complex coordinates q_c (n,) of the eigenvector nearest ``eigenvalue`` at ``speed``."""
    from motoflex_ros.vehicle.modes import eigen_decomposition
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


def _log_animated(rec, base, shapes, rotations, translations, timeline, times):
    """Shapes moved by their frames' poses (n_t, n_frames, ...) on ``timeline`` at ``times``."""
    index = (rr.TimeColumn(timeline, sequence=times) if timeline != TIMELINE
             else rr.TimeColumn(TIMELINE, duration=times))
    for name, frame, archetype in shapes:
        rec.log(f"{base}/{name}/shape", archetype, static=True)
        rec.send_columns(f"{base}/{name}", indexes=[index], columns=rr.Transform3D.columns(
            translation=translations[:, frame], mat3x3=rotations[:, frame]))


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


def _log_mode(rec, lin, shapes, mode, speed, eigenvalue, offset):
    rows, lam = mode_rows(lin, speed, eigenvalue)
    base = f"/vehicle/modes/{mode}"
    rec.log(base, rr.Transform3D(translation=offset), static=True)
    rec.log(f"{base}/description", rr.TextDocument(
        f"{mode} at {ms_to_kmh(speed):.0f} km/h: lambda = {lam.real:.3f} {lam.imag:+.3f}i 1/s "
        f"({lam.imag / (2 * np.pi):.2f} Hz); exaggerated so the largest angle is "
        f"{MODE_AMPLITUDE_RAD} rad; two cycles on the {rv.MODE_TIMELINE} timeline."), static=True)
    from motoflex_ros.vehicle.poses import frame_poses
    _log_animated(rec, base, shapes, *frame_poses(lin.system.tree, rows), rv.MODE_TIMELINE,
                  np.arange(len(rows)))


def _log_road_test(rec, lin, shapes, speed):
    from motoflex_ros.vehicle.poses import world_poses
    from motoflex_ros.vehicle.response import steer_pulse_response
    names = tuple(lin.state_names)
    pulse = steer_pulse_response(lin, speed, outputs=names)
    n_angles = len(lin.system.indep_pos)          # roll and the joint angles
    factor = ROAD_AMPLITUDE_RAD / max(np.abs(pulse.outputs[:, :n_angles]).max(), 1e-12)
    joints = [n for n in names if n in {c.name for c in lin.system.tree.coordinates}]
    rv.log_joint_series(rec, joints, pulse.time,
                        np.column_stack([pulse.outputs[:, names.index(n)] for n in joints]))
    rec.log("/vehicle/road_test/description", rr.TextDocument(
        f"Steer-torque pulse {pulse.torque:g} N m for {pulse.duration:g} s at "
        f"{ms_to_kmh(speed):.0f} km/h; bodies in the world frame (x along the initial heading, "
        f"path and heading integrated), response scaled x{factor:.3g} (a larger pulse); joint "
        f"series true size."), static=True)
    poses = world_poses(lin, pulse.time, factor * pulse.outputs, speed)
    _log_animated(rec, "/vehicle/road_test", shapes, poses.rotations, poses.translations,
                  TIMELINE, pulse.time)
    return len(pulse.time)


def log_motorcycle(rec, model, speed_mps=DEFAULT_SPEED_MPS, modes=None, road_test=True,
                   joint_axes=True):
    """Log the motorcycle ``model`` (a VehicleModel): joint axes, weave and wobble, road test.

    ``modes``: {name: eigenvalue at speed_mps}; by default weave and wobble from the engine's
    own modal sweep. ``joint_axes`` False leaves the revolute joints' axes out (a bag's
    markers draw them). Returns the number of road-test samples (0 without ``road_test``).
    """
    from motoflex_ros.vehicle.linearize import linearize
    from motoflex_ros.vehicle.modes import modal_sweep
    lin = linearize(model)
    shapes = _shapes(model, lin.system.tree)
    for joint in model.joints if joint_axes else ():
        if joint.kind == "revolute":
            rv.log_joint_axis(rec, joint.name, joint.point, joint.axis)
    if modes is None:
        sweep = modal_sweep(lin, np.array([speed_mps]))
        modes = {m: sweep.modes[m][0] for m in ("weave", "wobble")}
    for k, (mode, eigenvalue) in enumerate(modes.items()):
        if np.isfinite(eigenvalue):
            _log_mode(rec, lin, shapes, mode, speed_mps, eigenvalue, (0.0, 2.0 * (k + 1), 0.0))
    return _log_road_test(rec, lin, shapes, speed_mps) if road_test else 0


def vehicle_model(vehicle="touring", identified=None):
    """(VehicleModel, description): the lumped 'static' variant of all components identified in
    ``identified`` (identify-format dict) when it can be built, else the rigid ``vehicle``."""
    from motoflex_ros.config import MOTORCYCLE_COMPONENTS, resolve_config
    from motoflex_ros.errors import MotoflexError
    from motoflex_ros.structures import load_component
    from motoflex_ros.study.variants import build_variant
    from motoflex_ros.vehicle.model import load_vehicle
    rigid = load_vehicle(resolve_config("vehicles", vehicle))
    names = [n for n in MOTORCYCLE_COMPONENTS if n in (identified or {})]
    if not names:
        return rigid, f"{vehicle} (rigid)"
    try:
        components = {n: load_component(n) for n in names}
        model = build_variant(rigid, "static", names, identified, components)
    except (MotoflexError, KeyError, ValueError) as exc:
        return rigid, f"{vehicle} (rigid; lumped 'static' variant not built: {exc})"
    return model, f"{vehicle}, lumped 'static' variant of {', '.join(names)}"
