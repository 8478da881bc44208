"""The motorcycle in the recording: bodies, joint axes, weave and wobble, road test, written
from a :class:`~motoflex_ros.vehicle.animation.MotorcycleMotion` (the core computes the motion;
this module only draws it).

Bodies are drawn as the linkage they are (tubes from each body's centre of mass to its joints
and wheel centres: frame, fork, Telelever arm, swingarm, torque strut) with their
equivalent-inertia ellipsoids (the uniform solid ellipsoid with the body's mass and principal
moments: a_i^2 = 5 (I_j + I_k - I_i) / (2 m)) translucent, and the wheels as tyre rings with
spokes; each mode in its colour (:data:`~.rerun_vehicle.MODE_COLORS`), labelled.
"""
import numpy as np
import rerun as rr
from scipy.spatial.transform import Rotation

from motoflex_ros.record import rerun_vehicle as rv
from motoflex_ros.record.rerun_log import TIMELINE
from motoflex_ros.units import ms_to_kmh
from motoflex_ros.vehicle.outline import body_attachments

__all__ = ["log_motorcycle", "ellipsoid_half_sizes", "MIN_HALF_SIZE", "body_geometry",
           "wheel_ring", "body_group", "mode_label", "COMPONENT_COLORS", "posed_body_geometry",
           "MODE_SPACING_M"]

MIN_HALF_SIZE = 0.02


def ellipsoid_half_sizes(mass, principal_moments):
    """Semi-axes [m] of the uniform solid ellipsoid of ``mass`` [kg] and principal moments
    [kg m^2]: a_i = sqrt(5 (I_j + I_k - I_i) / (2 m)), at least :data:`MIN_HALF_SIZE`."""
    i = np.asarray(principal_moments, float)
    squares = 5.0 * (i.sum() - 2.0 * i) / (2.0 * mass)
    return np.maximum(np.sqrt(np.maximum(squares, 0.0)), MIN_HALF_SIZE)


COMPONENT_COLORS = {"frame": (150, 150, 165), "front": (70, 140, 210),
                    "rear": (60, 170, 90), "rider": (230, 160, 60), "wheel": (40, 40, 40)}
"""Colours of the road test's bodies by what they belong to (the modes take their mode's)."""
_FRONT = ("fork", "telelever", "front")
_REAR = ("swingarm", "strut", "carrier", "rear")
STICK_RADIUS_M = 0.02
MODE_SPACING_M = 4.0
"""The modes stand one behind the other along x, this far apart [m]: seen from the side, each
with its label above it."""
RING_POINTS = 48


def body_group(name):
    """'frame', 'front', 'rear' or 'rider': which part of the motorcycle a body belongs to."""
    if "rider" in name:
        return "rider"
    if any(k in name for k in _FRONT):
        return "front"
    if any(k in name for k in _REAR):
        return "rear"
    return "frame"


def body_geometry(model, reference=None, color=None):
    """{body name: [archetype]} drawing each body a person recognises, in the coordinates of
    its rerun entity: the body's equivalent-inertia ellipsoid (bodies with mass, translucent)
    and tubes (capsules) from its hub (centre of mass, or its first joint when massless) to
    each joint and wheel centre it holds, so frame, fork, Telelever arm, swingarm and torque
    strut show as the linkage they are. ``reference`` {body: point [m]} is subtracted (the
    bag's poses are at the centre of mass); default none (the model's rest frame). ``color``
    (a mode's) draws every tube in it and leaves the ellipsoids out: the linkage moving."""
    shapes = {}
    attached = body_attachments(model)
    for body in model.bodies:
        points = attached[body.name]
        if not points and body.mass <= 0:
            continue
        hub = np.asarray(body.com, float) if body.mass > 0 else points[0]
        origin = np.zeros(3) if reference is None else np.asarray(reference[body.name], float)
        tube = color or COMPONENT_COLORS[body_group(body.name)]
        parts = [_capsule(hub - origin, p - origin, tube) for p in points
                 if np.linalg.norm(p - hub) > 1e-3]
        if body.mass > 0:
            parts.append(_bulk(body, hub - origin, [p - origin for p in points], tube))
        shapes[body.name] = [p for p in parts if p is not None]
    return shapes


def _bulk(body, hub, points, color):
    """What gives a body its bulk: the rider a torso (a capsule from the lean joint up through
    the centre of mass), the frame a box of engine and tank (its equivalent-inertia ellipsoid's
    half sizes times 0.45, at most 0.22 m); other bodies none (their tubes say enough)."""
    group = body_group(body.name)
    if group == "rider" and points:
        return _capsule(points[0], hub + 0.6 * (hub - points[0]), color, radius=0.13)
    if group == "frame" and body.mass > 50.0:
        moments, axes = np.linalg.eigh(body.inertia)
        if np.linalg.det(axes) < 0:
            axes[:, 0] *= -1
        half = np.minimum(0.45 * ellipsoid_half_sizes(body.mass, moments), 0.22)
        return rr.Boxes3D(centers=[hub], half_sizes=[half],
                          quaternions=[Rotation.from_matrix(axes).as_quat()],
                          colors=[color], fill_mode="solid")
    return None


def _capsule(start, end, color, radius=STICK_RADIUS_M):
    """A tube of ``radius`` [m] from ``start`` to ``end`` [m]."""
    axis = end - start
    length = float(np.linalg.norm(axis))
    if length < 1e-6:
        return None
    z = axis / length
    rotation, _ = Rotation.align_vectors([z], [[0.0, 0.0, 1.0]])
    return rr.Capsules3D(lengths=[length], radii=[radius], translations=[start],
                         quaternions=[rotation.as_quat()], colors=[color])


def wheel_ring(wheel, color=COMPONENT_COLORS["wheel"], reference=None):
    """A wheel as a tyre ring (a circle of radius r - r_c [m], drawn r_c thick, in the wheel
    plane) with three spokes, so its spin shows."""
    centre = np.asarray(wheel.centre, float) - (0.0 if reference is None else reference)
    axis = np.asarray(wheel.axis, float) / np.linalg.norm(wheel.axis)
    u = np.cross(axis, [0.0, 0.0, 1.0])
    u = u / np.linalg.norm(u) if np.linalg.norm(u) > 1e-9 else np.array([1.0, 0.0, 0.0])
    v = np.cross(axis, u)
    ring = wheel.radius - wheel.crown_radius
    phi = np.linspace(0.0, 2 * np.pi, RING_POINTS + 1)
    circle = centre + ring * (np.outer(np.cos(phi), u) + np.outer(np.sin(phi), v))
    spokes = [[centre, centre + ring * (np.cos(a) * u + np.sin(a) * v)]
              for a in (0.0, 2 * np.pi / 3, 4 * np.pi / 3)]
    return rr.LineStrips3D([circle, *spokes], radii=[wheel.crown_radius] + [0.006] * 3,
                           colors=[color] * 4)


def posed_body_geometry(model, names):
    """{name: [archetype]} of the bodies ``names`` whose poses are given at their centres of
    mass (a bag's /vehicle/bodies), each with the wheel it carries (a massless carrier, not
    posed, passes its wheel to its parent); names the model does not have are left out."""
    coms = {b.name: np.asarray(b.com, float) for b in model.bodies}
    geometry = body_geometry(model, reference=coms)
    out = {n: list(geometry.get(n, [])) for n in names if n in coms}
    parents = {j.child: j.parent for j in model.joints}
    for wheel in model.wheels:
        carrier = wheel.carrier
        while carrier not in out and carrier in parents:   # a massless carrier: its parent
            carrier = parents[carrier]
        if carrier in out:
            out[carrier].append(wheel_ring(wheel, reference=coms[carrier]))
    return out


def _shapes(model, tree, color=None):
    """[(entity name, frame index, [archetype])] of the bodies and the wheels (all in
    ``color`` when given)."""
    geometry = body_geometry(model, color=color)
    shapes = [(name, tree.body_frames[name], parts) for name, parts in geometry.items()
              if name in tree.body_frames and parts]
    for wheel, frame in zip(model.wheels, tree.wheel_frames):
        shapes.append((f"{wheel.name}_wheel", frame,
                       [wheel_ring(wheel, color or COMPONENT_COLORS["wheel"])]))
    return shapes


def _log_animated(rec, base, shapes, rotations, translations, indexes):
    """Shapes moved by their frames' poses (n_t, n_frames, ...) over the time ``indexes``."""
    for name, frame, parts in shapes:
        for k, part in enumerate(parts):
            rec.log(f"{base}/{name}/shape/{k}", part, static=True)
        rec.send_columns(f"{base}/{name}", indexes=indexes, columns=rr.Transform3D.columns(
            translation=translations[:, frame], mat3x3=rotations[:, frame]))


def mode_label(mode):
    """'weave at 100 km/h: 2.93 Hz, Re -1.23 1/s': what a mode's label in 3D says."""
    lam = mode.eigenvalue
    return (f"{mode.name} at {ms_to_kmh(mode.speed):.0f} km/h: {lam.imag / (2 * np.pi):.2f} Hz,"
            f" Re {lam.real:.2f} 1/s")


def _log_mode(rec, model, tree, mode, offset, sim_span_s=None):
    """One mode beside the others, in its colour, labelled, animated on ``mode_frame`` and
    (``sim_span_s`` [s]) over the run's ``sim_time`` too, so it moves on the timeline the
    viewer opens on."""
    base = f"/vehicle/modes/{mode.name}"
    lam = mode.eigenvalue
    color = rv.MODE_COLORS.get(mode.name, (120, 120, 120))
    rec.log(base, rr.Transform3D(translation=offset), static=True)
    rec.log(f"{base}/description", rr.TextDocument(
        f"{mode.name} at {ms_to_kmh(mode.speed):.0f} km/h: lambda = {lam.real:.3f} "
        f"{lam.imag:+.3f}i 1/s ({lam.imag / (2 * np.pi):.2f} Hz); exaggerated so the largest "
        f"angle is {mode.amplitude_rad} rad; two cycles on the {rv.MODE_TIMELINE} timeline "
        f"and over the run's {TIMELINE}."), static=True)
    # labels one above the other (each mode's a step higher): they never share a line
    rec.log(f"{base}/label", rr.Points3D([[0.75, 0.0, 1.6 + 0.45 * offset[0] / MODE_SPACING_M]],
                                         labels=[mode_label(mode)],
                                         colors=[color], radii=0.01, show_labels=True),
            static=True)
    frames = np.arange(len(mode.rotations))
    indexes = [rr.TimeColumn(rv.MODE_TIMELINE, sequence=frames)]
    if sim_span_s:
        indexes.append(rr.TimeColumn(TIMELINE, duration=np.linspace(0.0, sim_span_s,
                                                                    len(frames))))
    _log_animated(rec, base, _shapes(model, tree, color), mode.rotations, mode.translations,
                  indexes)


def _log_road_test(rec, shapes, road):
    rv.log_joint_series(rec, list(road.joints), road.time, road.joint_series)
    rec.log("/vehicle/road_test/description", rr.TextDocument(
        f"Steer-torque pulse {road.torque:g} N m for {road.duration:g} s at "
        f"{ms_to_kmh(road.speed):.0f} km/h; bodies in the world frame (x along the initial "
        f"heading, path and heading integrated), response scaled x{road.factor:.3g} (a larger "
        f"pulse); joint series true size."), static=True)
    _log_animated(rec, "/vehicle/road_test", shapes, road.rotations, road.translations,
                  [rr.TimeColumn(TIMELINE, duration=road.time)])
    return len(road.time)


def log_motorcycle(rec, motion, joint_axes=True, sim_span_s=None):
    """Log a MotorcycleMotion: bodies, joint axes (``joint_axes`` False leaves the revolute
    joints' axes out: a bag's markers draw them), each mode beside the others (also over
    ``sim_span_s`` [s] of ``sim_time`` when given), the road test (when ``motion.road``).
    Returns the number of road-test samples (0 without one)."""
    for joint in motion.model.joints if joint_axes else ():
        if joint.kind == "revolute":
            rv.log_joint_axis(rec, joint.name, joint.point, joint.axis)
    for k, mode in enumerate(motion.modes.values()):
        _log_mode(rec, motion.model, motion.tree, mode, (MODE_SPACING_M * k, 0.0, 0.0),
                  sim_span_s)
    if motion.road is None:
        return 0
    return _log_road_test(rec, _shapes(motion.model, motion.tree), motion.road)
