"""Tree kinematics of a vehicle on a 6-DOF floating base (numerical TMT/Kane building blocks).

Every generalised coordinate q_k moves one frame relative to its parent frame (frame 0 is the
ground, coordinate k creates frame k + 1): prismatic along a unit axis, or revolute about a unit
axis through a point, both given in the reference configuration. The floating base is the chain
x, y, z, yaw (z), roll (x), pitch (y) about the origin; x and y are quasi-coordinates whose
speeds are the forward and lateral velocity in the heading frame (the ground axes yawed by the
yaw angle), so that x, y and yaw are cyclic under the symmetry of flat ground. A pose
maps reference positions to current ones, x = R x_ref + t. Twists are (omega, v_O): angular
velocity and velocity of the frame-fixed point at the world origin, so a point x moves with
v = v_O + omega x x; bias accelerations are the twist derivatives at zero generalised
acceleration. All arithmetic is complex-step safe.
"""
from dataclasses import dataclass

import numpy as np

from motoflex_ros.errors import ModelError
from motoflex_ros.spatial import cross, rotation, skew

__all__ = ["Coordinate", "MassItem", "Tree", "FrameState", "CutJoint", "compile_tree",
           "frame_states", "coordinate_names_of", "BASE_NAMES"]

BASE_NAMES = ("x", "y", "z", "yaw", "roll", "pitch")
_BASE_AXES = ((1, 0, 0), (0, 1, 0), (0, 0, 1), (0, 0, 1), (1, 0, 0), (0, 1, 0))


@dataclass(frozen=True)
class Coordinate:
    """One generalised coordinate: kind 'prismatic', 'revolute' or 'heading' (base x, y: a
    translation along a heading-frame axis), group 'base', 'joint' or
    'spin'; stiffness [N m/rad] and damping [N m s/rad] of a spring/damper acting on it."""

    name: str
    kind: str
    group: str
    parent_frame: int
    axis: np.ndarray
    point: np.ndarray
    stiffness: float = 0.0
    damping: float = 0.0
    locked: bool = False


@dataclass(frozen=True)
class CutJoint:
    """A joint that closes a kinematic loop: both bodies are already in the tree, so instead of
    coordinates it adds constraint equations between the parent frame and the child frame
    (:mod:`motoflex_ros.vehicle.loops`). ``joint`` is the model's Joint."""

    joint: object
    parent_frame: int
    child_frame: int


@dataclass(frozen=True)
class MassItem:
    """A rigid mass attached to a frame: mass [kg], com [m], inertia [kg m^2] (reference)."""

    name: str
    frame: int
    mass: float
    com: np.ndarray
    inertia: np.ndarray


@dataclass(frozen=True)
class Tree:
    """Compiled kinematic tree: coordinates, masses, frames of bodies and wheels."""

    coordinates: tuple
    masses: tuple
    body_frames: dict
    wheel_frames: tuple
    cut_joints: tuple = ()

    def index(self, name):
        """Index of the coordinate called ``name``."""
        return next(k for k, c in enumerate(self.coordinates) if c.name == name)


@dataclass(frozen=True)
class FrameState:
    """Pose (R, t), twist (w, v0), bias twist derivative (dw, dv0) and twist Jacobians of a
    frame (3 x n each: w = Jw u, v0 = Jv u)."""

    R: np.ndarray
    t: np.ndarray
    w: np.ndarray
    v0: np.ndarray
    dw: np.ndarray
    dv0: np.ndarray
    Jw: np.ndarray
    Jv: np.ndarray

    def point_velocity_jacobian(self, x):
        """3 x n Jacobian of the velocity of the frame-fixed point currently at x [m]."""
        return self.Jv - skew(x) @ self.Jw


def _base_coordinates():
    zero = np.zeros(3)
    kinds = ("heading", "heading", "prismatic", "revolute", "revolute", "revolute")
    return [Coordinate(name, kinds[k], "base", k, np.array(_BASE_AXES[k], float), zero)
            for k, name in enumerate(BASE_NAMES)]


def _wheel_mass(wheel, frame):
    return MassItem(wheel.name, frame, wheel.mass, wheel.centre, wheel.inertia)


def coordinate_names_of(joint):
    """Names of a joint's coordinates: the joint's name for the first, then name_2, name_3
    (so a role naming a spherical steering joint is its rotation about the steering axis)."""
    return [joint.name] + [f"{joint.name}_{i}" for i in range(2, len(joint.axes) + 1)]


def _add_joint_coordinates(joint, coords, frames):
    """Append the joint's coordinates (a chain for universal and spherical joints)."""
    parent = frames[joint.parent]
    kind = joint.kind if joint.kind in ("prismatic", "modal") else "revolute"
    for i, (name, axis) in enumerate(zip(coordinate_names_of(joint), joint.axes)):
        spring = (joint.stiffness, joint.damping) if i == 0 else (0.0, 0.0)
        coords.append(Coordinate(name, kind, "joint", parent, axis, joint.point, *spring,
                                 locked=joint.locked))
        parent = len(coords)
    frames[joint.child] = parent


def _attach_joints(model, coords, frames):
    """Attach the joints breadth first from the root; a joint whose child is already attached
    closes a loop and becomes a CutJoint, and so does every joint marked ``cut`` (applied after
    the tree). Returns the cut joints."""
    pending = [j for j in model.joints if not j.cut]
    cuts = []
    while pending:
        ready = [j for j in pending if j.parent in frames]
        if not ready:
            names = ", ".join(j.name for j in pending)
            raise ModelError(f"{model.source}: joints {names} do not connect to the root body "
                             f"'{model.root}' (a joint hangs its child from its parent: check "
                             "that every parent is reached from the root)")
        for joint in ready:
            pending.remove(joint)
            if joint.child in frames:
                cuts.append(joint)
            elif joint.kind == "fixed":
                frames[joint.child] = frames[joint.parent]
            else:
                _add_joint_coordinates(joint, coords, frames)
    for joint in model.joints:
        if not joint.cut:
            continue
        missing = [b for b in (joint.parent, joint.child) if b not in frames]
        if missing:
            raise ModelError(f"{model.source}: the cut joint '{joint.name}' joins body "
                             f"'{missing[0]}', which no tree joint attaches to the root "
                             f"'{model.root}' (a cut joint closes a loop between two attached "
                             "bodies)")
        cuts.append(joint)
    return [CutJoint(j, frames[j.parent], frames[j.child]) for j in cuts]
def compile_tree(model):
    """Compile a VehicleModel into coordinates and masses (base, joints, wheel spins)."""
    coords = _base_coordinates()
    frames = {model.root: len(coords)}
    cuts = _attach_joints(model, coords, frames)
    missing = [b.name for b in model.bodies if b.name not in frames]
    if missing:
        raise ModelError(f"{model.source}: bodies {', '.join(missing)} are not attached")
    wheel_frames = []
    for wheel in model.wheels:
        coords.append(Coordinate(f"{wheel.name}_spin", "revolute", "spin",
                                 frames[wheel.carrier], wheel.axis, wheel.centre))
        wheel_frames.append(len(coords))
    masses = [MassItem(b.name, frames[b.name], b.mass, b.com, b.inertia) for b in model.bodies]
    masses += [_wheel_mass(w, f) for w, f in zip(model.wheels, wheel_frames)]
    return Tree(tuple(coords), tuple(masses), dict(frames), tuple(wheel_frames), tuple(cuts))


def _child_state(coord, k, parent, q, u, heading):
    if coord.kind == "modal":
        # a modal amplitude of a superelement moves no frame: its Jacobian columns stay zero
        return parent
    a_w = parent.R @ coord.axis
    a_dot = cross(parent.w, a_w)
    if coord.kind == "heading":
        # translation along a heading-frame axis: the axis turns with the yaw rate
        a_w = heading[0] @ coord.axis
        a_dot = heading[1] * cross(np.array([0.0, 0.0, 1.0]), a_w)
    if coord.kind == "revolute":
        if q[k] == 0:
            # exactly zero (no perturbation flows through it): the rotation is the identity,
            # the same value and derivative Rodrigues would give, without computing it
            R, t = parent.R, parent.t
        else:
            rel = rotation(coord.axis, q[k])
            R = parent.R @ rel
            t = parent.R @ (coord.point - rel @ coord.point) + parent.t
        s_w = parent.R @ coord.point + parent.t
        s_dot = parent.v0 + cross(parent.w, s_w)
        col_w, col_v = a_w, cross(s_w, a_w)
        dcol_w, dcol_v = a_dot, cross(s_dot, a_w) + cross(s_w, a_dot)
    else:
        R, t = parent.R, parent.t + q[k] * a_w
        col_w, col_v = 0.0 * a_w, a_w
        dcol_w, dcol_v = 0.0 * a_w, a_dot
    Jw, Jv = parent.Jw.copy(), parent.Jv.copy()
    Jw[:, k], Jv[:, k] = col_w, col_v
    return FrameState(R, t, parent.w + col_w * u[k], parent.v0 + col_v * u[k],
                      parent.dw + dcol_w * u[k], parent.dv0 + dcol_v * u[k], Jw, Jv)


def frame_states(tree, q, u):
    """FrameState of every frame (index 0 ground) at coordinates q and speeds u."""
    n = len(tree.coordinates)
    dtype = np.result_type(q, u, float)
    zero3, zero_j = np.zeros(3, dtype), np.zeros((3, n), dtype)
    states = [FrameState(np.eye(3, dtype=dtype), zero3, zero3, zero3, zero3, zero3,
                         zero_j, zero_j)]
    yaw = BASE_NAMES.index("yaw")
    heading = (rotation(np.array([0.0, 0.0, 1.0]), q[yaw]), u[yaw])
    for k, coord in enumerate(tree.coordinates):
        states.append(_child_state(coord, k, states[coord.parent_frame], q, u, heading))
    return states
