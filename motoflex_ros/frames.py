"""The rig's coordinate frames as one tf tree (REP-103 axes: x forward, y left, z up).

One root per rig, ``world``: the lab. Under it

- the bench of each component (``<c>_clamp``: the paper's component frame, clamp at O, placed
  at the component's O in the vehicle frame plus ``BENCH_SPACING_M`` sideways per bench, as
  the rerun recording places them; static), its loaded end ``<c>_loaded_end`` (moving: at q0
  plus the simulated displacement and rotation of the loaded end, :func:`loaded_end_transform`)
  and the sensor's markers ``<c>_marker_<i>`` at their offsets from q0 (static children of the
  loaded end: they move with it, as the sensor's rigid marker set does);
- the road test (``odom``, ``ROAD_OFFSET_M`` beside the benches, x along the initial heading),
  the motorcycle's main frame body ``vehicle`` (the reference-configuration axes carried by the
  frame body: the joint axes are drawn there) and one frame per body with mass,
  ``vehicle/<body>``, at its centre of mass with the reference axes.

Everything here is numbers and names (no ROS): :class:`FrameTransform` is what a
geometry_msgs/TransformStamped carries, parent -> child, x_parent = R x_child + t.
"""
from dataclasses import dataclass

import numpy as np

__all__ = ["ROOT_FRAME", "ODOM_FRAME", "VEHICLE_FRAME", "BENCH_SPACING_M", "ROAD_OFFSET_M",
           "FrameTransform", "clamp_frame", "loaded_end_frame", "marker_frame", "body_frame",
           "bench_transforms", "loaded_end_transform", "road_transform", "vehicle_transforms",
           "body_com_poses"]

ROOT_FRAME = "world"
ODOM_FRAME = "odom"
VEHICLE_FRAME = "vehicle"
BENCH_SPACING_M = 1.0     # lateral spacing of the components' benches [m]
ROAD_OFFSET_M = (0.0, -3.0, 0.0)   # odom in the world frame: the road beside the benches [m]

_IDENTITY = np.eye(3)


@dataclass(frozen=True)
class FrameTransform:
    """Pose of frame ``child`` in frame ``parent``: rotation (3, 3), translation [m] (3,)."""

    parent: str
    child: str
    rotation: np.ndarray
    translation: np.ndarray


def clamp_frame(component):
    """Frame of a component's bench data: its clamp (the paper's component frame)."""
    return f"{component}_clamp"


def loaded_end_frame(component):
    """The nominal loaded end of a component (at q0 in its clamp frame)."""
    return f"{component}_loaded_end"


def marker_frame(component, index):
    """Marker ``index`` of a component's displacement sensor."""
    return f"{component}_marker_{index}"


def body_frame(body):
    """Frame of a motorcycle body at its centre of mass."""
    return f"{VEHICLE_FRAME}/{body}"


def bench_transforms(benches):
    """Static FrameTransforms of the benches: ``benches`` is a list of (component name, O in
    the vehicle frame [m] (3,), q0 [m] (3,), marker offsets from q0 [m] (n, 3)); the k-th
    in sorted name order stands k BENCH_SPACING_M to the left (as in the rerun recording).
    The loaded end between clamp and markers moves: :func:`loaded_end_transform`."""
    out = []
    for k, (name, origin, _, markers) in enumerate(sorted(benches, key=lambda b: b[0])):
        place = np.asarray(origin, float) + np.array([0.0, BENCH_SPACING_M * k, 0.0])
        out.append(FrameTransform(ROOT_FRAME, clamp_frame(name), _IDENTITY, place))
        out += [FrameTransform(loaded_end_frame(name), marker_frame(name, i), _IDENTITY,
                               np.asarray(m, float)) for i, m in enumerate(markers)]
    return out


def loaded_end_transform(component, q0, rotation, displacement):
    """Clamp -> loaded end of ``component``: at q0 [m] (3,) moved by ``displacement`` [m] (3,)
    and turned by ``rotation`` (3, 3), the loaded end's simulated motion in the clamp frame."""
    return FrameTransform(clamp_frame(component), loaded_end_frame(component),
                          np.asarray(rotation, float),
                          np.asarray(q0, float) + np.asarray(displacement, float))


def road_transform():
    """Static world -> odom."""
    return FrameTransform(ROOT_FRAME, ODOM_FRAME, _IDENTITY, np.asarray(ROAD_OFFSET_M, float))


def body_com_poses(rotations, translations, coms):
    """World poses of body centres of mass: the kinematic frames' rotations (n, 3, 3) and
    translations [m] (n, 3) (x = R x_ref + t) and the reference centres of mass [m] (n, 3)
    give (R, R com + t)."""
    rotations = np.real(np.asarray(rotations))
    return rotations, (np.einsum("bij,bj->bi", rotations, np.asarray(coms, float))
                       + np.real(np.asarray(translations)))


def vehicle_transforms(base_rotation, base_translation, names, rotations, positions):
    """Odom -> vehicle (the main frame body's kinematic frame: rotation (3, 3), translation
    [m]) and vehicle -> vehicle/<name> for each body from its world pose at the centre of mass
    (rotations (n, 3, 3), positions [m] (n, 3), e.g. :func:`body_com_poses`)."""
    base_r = np.real(np.asarray(base_rotation))
    base_t = np.real(np.asarray(base_translation))
    out = [FrameTransform(ODOM_FRAME, VEHICLE_FRAME, base_r, base_t)]
    for name, r, p in zip(names, rotations, positions):
        out.append(FrameTransform(VEHICLE_FRAME, body_frame(name), base_r.T @ r,
                                  base_r.T @ (np.asarray(p) - base_t)))
    return out
