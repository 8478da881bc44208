"""Closed kinematic loops and locked coordinates as holonomic constraints g(q) = 0.

A cut joint (a joint whose child the tree already reached, :class:`~.kinematics.CutJoint`)
holds its two frames together at its point P (reference configuration) by

- translation rows  g_i = n_i . (x_c - x_p)   along unit directions n_i fixed in the parent
  (x_p, x_c the parent's and the child's material points at P): all three axes for a
  spherical, universal, revolute or fixed joint, the two normals to the axis for a prismatic
  one;
- rotation rows  g_ab = a . b  for unit vectors a fixed in the parent and b fixed in the
  child, normal to each other in the reference configuration: (axis, axis2) for a universal
  joint, (n_1, axis) and (n_2, axis) for a revolute one, the three pairs of frame axes for a
  prismatic or fixed one.

A locked coordinate k (frozen suspension travel) adds g = q_k. The engine differentiates
these rows exactly: with twists (omega, v_O) of the frames (kinematics.py),

    g_i'  = n_i . (x_c' - x_p') + (n_i x d) . omega_p,          d = x_c - x_p,
    g_ab' = (a x b) . (omega_p - omega_c),

so the velocity rows are G u = g' and the acceleration rows G u' + bias = g'' with the bias
collecting every term that does not multiply u':

    bias_i  = n_i . (b_c - b_p) + 2 (omega_p x n_i) . (x_c' - x_p')
              + (alpha0_p x n_i + omega_p x (omega_p x n_i)) . d,
    bias_ab = (a x b) . (alpha0_p - alpha0_c) + ((omega_p x a) x b + a x (omega_c x b))
              . (omega_p - omega_c),

b the bias acceleration of a material point (v0' + alpha0 x x + omega x x' at u' = 0) and
alpha0 the bias angular acceleration. Units: translation rows in m (velocity m/s), rotation
rows dimensionless (rad/s); every expression is complex-step safe.
"""
from dataclasses import dataclass

import numpy as np

from motoflex_ros.spatial import cross

__all__ = ["ConstraintRows", "cut_joint_rows", "lock_rows", "loop_rows", "n_rows_of",
           "translation_directions", "rotation_pairs"]

_AXES = np.eye(3)
_FRAME_PAIRS = ((_AXES[1], _AXES[2]), (_AXES[2], _AXES[0]), (_AXES[0], _AXES[1]))


def _normals(axis):
    """Two unit vectors normal to ``axis`` and to each other (a fixed, deterministic choice)."""
    trial = _AXES[int(np.argmin(np.abs(axis)))]
    first = trial - (trial @ axis) * axis
    first = first / np.linalg.norm(first)
    return first, np.cross(axis, first)


def translation_directions(joint):
    """Unit directions (reference configuration, fixed in the parent) the joint holds."""
    if joint.kind == "prismatic":
        return _normals(joint.axis)
    return tuple(_AXES)


def rotation_pairs(joint):
    """Pairs (a in the parent, b in the child) of unit vectors the joint keeps normal."""
    if joint.kind == "spherical":
        return ()
    if joint.kind == "universal":
        return ((joint.axis, joint.axis2),)
    if joint.kind == "revolute":
        return tuple((n, joint.axis) for n in _normals(joint.axis))
    return _FRAME_PAIRS


def n_rows_of(joint):
    """Number of constraint equations a cut joint adds."""
    return len(translation_directions(joint)) + len(rotation_pairs(joint))


@dataclass(frozen=True)
class ConstraintRows:
    """Holonomic constraints at one state: values g (m,), velocity rows G (m, n) with
    g' = G u, and bias (m,) with g'' = G u' + bias."""

    g: np.ndarray
    G: np.ndarray
    bias: np.ndarray


def _point(frame, reference):
    """Position, velocity, velocity Jacobian and bias acceleration of a material point."""
    x = frame.R @ reference + frame.t
    xdot = frame.v0 + cross(frame.w, x)
    bias = frame.dv0 + cross(frame.dw, x) + cross(frame.w, xdot)
    return x, xdot, frame.point_velocity_jacobian(x), bias


def cut_joint_rows(cut, frames):
    """(g, G, bias) lists of one cut joint (module docstring)."""
    joint = cut.joint
    fp, fc = frames[cut.parent_frame], frames[cut.child_frame]
    xp, xdp, Jp, bp = _point(fp, joint.point)
    xc, xdc, Jc, bc = _point(fc, joint.point)
    d, dd = xc - xp, xdc - xdp
    g, rows, bias = [], [], []
    for n_ref in translation_directions(joint):
        n = fp.R @ n_ref
        wn = cross(fp.w, n)
        g.append(n @ d)
        rows.append(n @ (Jc - Jp) + cross(n, d) @ fp.Jw)
        bias.append(n @ (bc - bp) + 2.0 * (wn @ dd)
                    + (cross(fp.dw, n) + cross(fp.w, wn)) @ d)
    for a_ref, b_ref in rotation_pairs(joint):
        a, b = fp.R @ a_ref, fc.R @ b_ref
        c = cross(a, b)
        c_dot = cross(cross(fp.w, a), b) + cross(a, cross(fc.w, b))
        g.append(a @ b)
        rows.append(c @ (fp.Jw - fc.Jw))
        bias.append(c @ (fp.dw - fc.dw) + c_dot @ (fp.w - fc.w))
    return g, rows, bias


def lock_rows(tree, q):
    """(g, G, bias) lists of the locked coordinates: g = q_k, G = e_k, no bias."""
    n = len(tree.coordinates)
    g, rows = [], []
    for k, coord in enumerate(tree.coordinates):
        if coord.locked:
            row = np.zeros(n, np.result_type(q, float))
            row[k] = 1.0
            g.append(q[k])
            rows.append(row)
    return g, rows, [0.0 * q[0]] * len(g)


def loop_rows(tree, frames, q):
    """ConstraintRows of every cut joint (in tree order), then of every locked coordinate."""
    g, rows, bias = [], [], []
    for cut in tree.cut_joints:
        for out, part in zip((g, rows, bias), cut_joint_rows(cut, frames)):
            out.extend(part)
    for out, part in zip((g, rows, bias), lock_rows(tree, q)):
        out.extend(part)
    n = len(tree.coordinates)
    dtype = np.result_type(q, frames[-1].R)
    if not g:
        return ConstraintRows(np.zeros(0, dtype), np.zeros((0, n), dtype), np.zeros(0, dtype))
    return ConstraintRows(np.array(g, dtype), np.array(rows, dtype), np.array(bias, dtype))
