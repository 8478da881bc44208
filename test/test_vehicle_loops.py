"""Closed kinematic loops in the vehicle engine (issue 12): mechanisms with known answers.

1. A planar four-bar linkage (crank, coupler, rocker on a fixed base, in the horizontal plane so
   that gravity does no work) with a torsional spring on the crank: omega^2 = k / M_eff with
   M_eff = J_2 + m_3 |v_G3 / omega_2|^2 + I_3 (omega_3 / omega_2)^2 + J_4 (omega_4 / omega_2)^2
   from the textbook velocity ratios of the loop equation a e^(i th2) + b e^(i th3) =
   d + c e^(i th4) (Norton, Design of Machinery, eqs. 6.18):
       omega_3 / omega_2 = a sin(th4 - th2) / (b sin(th3 - th4)),
       omega_4 / omega_2 = a sin(th2 - th3) / (c sin(th4 - th3)).
2. A spatial loop (two cranks on skew axes joined by a massless coupler of fixed length, a
   universal joint at one end and a spherical joint at the other) under gravity, with both
   cranks' centres of mass off their axes so that the loop carries a static internal force in
   the reference configuration: the second formulation here solves the closure in closed form
   (A cos th2 + B sin th2 = C), and takes omega^2 = V''(0) / M_eff(0) from the potential and
   kinetic energy along that exact one-degree-of-freedom motion. V'' contains the loop's
   curvature d^2 th2 / d th1^2 times the crank-2 gravity moment: wrong constraint bias or
   Jacobian terms in the engine would show there.
"""
import numpy as np
import pytest

from motoflex_ros.errors import ConfigError, ModelError
from motoflex_ros.vehicle.dynamics import build_system
from motoflex_ros.vehicle.linearize import linearize
from motoflex_ros.vehicle.model import vehicle_from_dict

G = 9.81


def _body(mass, com, inertia=(0.010, 0.012, 0.015)):
    return {"mass": mass, "com": [float(c) for c in com],
            "inertia": {"xx": inertia[0], "yy": inertia[1], "zz": inertia[2]}}


def _frequency(model):
    """Largest undamped natural frequency [rad/s] of the linearized model (one speed)."""
    lam = linearize(model).eigenvalues(1.0)
    return float(np.max(np.abs(lam.imag)))


# --- 1. planar four-bar ------------------------------------------------------------------------

A_LEN, B_LEN, C_LEN, D_LEN = 0.30, 0.70, 0.60, 0.80
THETA2 = np.radians(60.0)
K_CRANK = 250.0                   # [N m/rad]
M2, M3, M4 = 1.2, 2.0, 1.5        # [kg]
IZZ = 0.015                       # [kg m^2] about each body's centre of mass, axis z


def _four_bar_points():
    a = A_LEN * np.array([np.cos(THETA2), np.sin(THETA2), 0.0])
    d = np.array([D_LEN, 0.0, 0.0])
    # C: intersection of the circles |C - B| = b and |C - D| = c, the upper (open) branch
    base = d - a
    dist = np.linalg.norm(base)
    along = (B_LEN ** 2 - C_LEN ** 2 + dist ** 2) / (2 * dist)
    height = np.sqrt(B_LEN ** 2 - along ** 2)
    e = base / dist
    normal = np.array([-e[1], e[0], 0.0])
    c = a + along * e + height * normal
    return np.zeros(3), a, c, d


def _four_bar_dict(**joint_overrides):
    o, b, c, d = _four_bar_points()
    coupler_dir = (c - b) / np.linalg.norm(c - b)
    joints = {
        "crank_pivot": {"type": "revolute", "parent": "ground", "child": "crank",
                        "axis": [0, 0, 1], "point": o.tolist(), "stiffness": K_CRANK},
        "rocker_pivot": {"type": "revolute", "parent": "ground", "child": "rocker",
                         "axis": [0, 0, 1], "point": d.tolist()},
        "coupler_pin": {"type": "universal", "parent": "crank", "child": "coupler",
                        "axis": [0, 0, 1], "axis2": [-coupler_dir[1], coupler_dir[0], 0.0],
                        "point": b.tolist()},
        "closing_pin": {"type": "spherical", "parent": "coupler", "child": "rocker",
                        "point": c.tolist()},
    }
    for name, override in joint_overrides.items():
        joints[name] = {**joints[name], **override}
    return {"name": "four_bar", "base": "fixed", "root": "ground", "gravity": G,
            "roles": {"crank": "crank_pivot"},      # keep the crank angle independent
            "bodies": {"ground": _body(1.0, o),
                       "crank": _body(M2, 0.5 * b, (0.010, 0.012, IZZ)),
                       "coupler": _body(M3, b + 0.4 * (c - b), (0.010, 0.012, IZZ)),
                       "rocker": _body(M4, d + 0.5 * (c - d), (0.010, 0.012, IZZ))},
            "joints": joints}


def _four_bar_analytic():
    _, b, c, d = _four_bar_points()
    th2 = THETA2
    th3 = np.arctan2(*(c - b)[1::-1])
    th4 = np.arctan2(*(c - d)[1::-1])
    w3 = A_LEN * np.sin(th4 - th2) / (B_LEN * np.sin(th3 - th4))
    w4 = A_LEN * np.sin(th2 - th3) / (C_LEN * np.sin(th4 - th3))
    z = np.array([0.0, 0.0, 1.0])
    g3 = b + 0.4 * (c - b)
    v_g3 = np.cross(z, b) + w3 * np.cross(z, g3 - b)           # per unit crank rate
    m_eff = (IZZ + M2 * np.sum((0.5 * b) ** 2) + M3 * v_g3 @ v_g3 + IZZ * w3 ** 2
             + (IZZ + M4 * np.sum((0.5 * (c - d)) ** 2)) * w4 ** 2)
    return np.sqrt(K_CRANK / m_eff)


def test_planar_four_bar_frequency_analytic():
    model = vehicle_from_dict(_four_bar_dict())
    system = build_system(model)
    assert [system.tree.coordinates[k].name for k in system.indep_pos] == ["crank_pivot"]
    np.testing.assert_allclose(_frequency(model), _four_bar_analytic(), rtol=1e-6)


def test_four_bar_does_not_depend_on_where_the_loop_is_cut():
    """Cutting the loop at the crank pin instead of the rocker pin (another spanning tree,
    other dependent coordinates) gives the same frequency."""
    data = _four_bar_dict()
    joints = data["joints"]
    o, b, c, d = _four_bar_points()
    coupler_dir = (b - c) / np.linalg.norm(b - c)
    joints["coupler_pin"] = {"type": "spherical", "parent": "crank", "child": "coupler",
                             "point": b.tolist()}
    joints["closing_pin"] = {"type": "universal", "parent": "rocker", "child": "coupler",
                             "axis": [0, 0, 1], "axis2": [-coupler_dir[1], coupler_dir[0], 0],
                             "point": c.tolist()}
    joints = {k: joints[k] for k in ("crank_pivot", "rocker_pivot", "closing_pin",
                                     "coupler_pin")}
    data["joints"] = joints
    system = build_system(vehicle_from_dict(data))
    assert [c.joint.name for c in system.tree.cut_joints] == ["coupler_pin"]
    np.testing.assert_allclose(_frequency(vehicle_from_dict(data)), _four_bar_analytic(),
                               rtol=1e-6)


# --- 2. spatial loop under gravity -------------------------------------------------------------

AXIS1 = np.array([0.0, 1.0, 0.0])                        # crank 1: lateral axis through O1
O1 = np.array([0.0, 0.0, 1.0])
AXIS2 = np.array([0.3, 0.8, 0.52]) / np.linalg.norm([0.3, 0.8, 0.52])   # crank 2: skew axis
O2 = np.array([0.9, 0.25, 0.7])
P1 = O1 + np.array([0.25, 0.0, 0.05])                    # crank pins (reference)
P2 = O2 + 0.3 * np.cross(AXIS2, [0.0, 0.0, 1.0]) / np.linalg.norm(np.cross(AXIS2, [0, 0, 1]))
M_1, M_2, K_1 = 3.0, 2.5, 5.0
R2_COM = np.array([0.05, -0.04, 0.12])                   # crank 2 com offset from O2


def _rot(axis, angle):
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * k @ k


def _closure_terms(theta1):
    """A, B, C of the closure A cos th2 + B sin th2 = C, i.e. |P1(th1) - P2(th2)| = L."""
    length2 = np.sum((P1 - P2) ** 2)
    p1 = O1 + _rot(AXIS1, theta1) @ (P1 - O1)
    r = P2 - O2
    r_par = (r @ AXIS2) * AXIS2
    e1, e2 = r - r_par, np.cross(AXIS2, r)
    w = p1 - O2 - r_par                      # |w - e1 cos th2 - e2 sin th2|^2 = L^2
    return 2 * (w @ e1), 2 * (w @ e2), w @ w + e1 @ e1 - length2


def _theta2(theta1, branch=None):
    """Closed-form crank-2 angle; the branch through th2 = 0 at th1 = 0."""
    if branch is None:
        branch = _BRANCH
    A, B, C = _closure_terms(theta1)
    phase = np.arctan(B / A) + (np.pi if np.real(A) < 0 else 0.0)   # atan2, complex-step safe
    angle = phase + branch * np.arccos(C / np.sqrt(A * A + B * B))
    return angle - 2 * np.pi * np.round(np.real(angle) / (2 * np.pi))


_BRANCH = next(sign for sign in (1.0, -1.0) if abs(_theta2(0.0, sign)) < 1e-9)


def _crank1_com():
    """Crank-1 com (off its axis) that balances crank 2's gravity moment through the loop at
    the reference: m1 dz1/dth1 + m2 dz2/dth1 = 0, and 4 cm below the axis."""
    h = 1e-20
    dth2 = (_theta2(1j * h)).imag / h
    dz2 = (np.cross(AXIS2, R2_COM) * dth2)[2]
    # dz1/dth1 = (AXIS1 x r1)_z = -r1_x for AXIS1 = y: choose r1_x to balance
    r1_x = M_2 * dz2 / M_1
    return O1 + np.array([r1_x, 0.0, -0.04])


def _spatial_dict():
    com1 = _crank1_com()
    coupler = (P2 - P1) / np.linalg.norm(P2 - P1)
    u_axis = np.cross(coupler, [0.0, 0.0, 1.0])
    u_axis /= np.linalg.norm(u_axis)
    return {"name": "spatial_loop", "base": "fixed", "root": "ground", "gravity": G,
            "bodies": {"ground": _body(1.0, [0, 0, 0]),
                       "crank1": _body(M_1, com1, (0.02, 0.03, 0.025)),
                       "coupler": {"mass": 0.0, "com": P1.tolist()},
                       "crank2": _body(M_2, O2 + R2_COM, (0.015, 0.02, 0.018))},
            "joints": {
                "pivot1": {"type": "revolute", "parent": "ground", "child": "crank1",
                           "axis": AXIS1.tolist(), "point": O1.tolist(), "stiffness": K_1},
                "pivot2": {"type": "revolute", "parent": "ground", "child": "crank2",
                           "axis": AXIS2.tolist(), "point": O2.tolist()},
                "pin1": {"type": "universal", "parent": "crank1", "child": "coupler",
                         "axis": u_axis.tolist(), "axis2": np.cross(coupler, u_axis).tolist(),
                         "point": P1.tolist()},
                "pin2": {"type": "spherical", "parent": "coupler", "child": "crank2",
                         "point": P2.tolist()}}}


def _spatial_second_formulation():
    """omega^2 = V''(0) / M_eff(0) along the closed-form motion th2(th1)."""
    data = _spatial_dict()
    b1, b2 = data["bodies"]["crank1"], data["bodies"]["crank2"]
    r1 = np.array(b1["com"]) - O1
    r2 = np.array(b2["com"]) - O2
    i1 = np.diag([b1["inertia"][k] for k in ("xx", "yy", "zz")])
    i2 = np.diag([b2["inertia"][k] for k in ("xx", "yy", "zz")])

    def potential(th1):
        z1 = (O1 + _rot(AXIS1, th1) @ r1)[2]
        z2 = (O2 + _rot(AXIS2, _theta2(th1)) @ r2)[2]
        return G * (M_1 * z1 + M_2 * z2) + 0.5 * K_1 * th1 ** 2

    def slope(th1):                       # complex-step dth2/dth1, then a real difference
        return (_theta2(th1 + 1e-20j)).imag / 1e-20

    h = 1e-4
    v2 = (potential(h) - 2 * potential(0.0) + potential(-h)) / h ** 2
    dth2 = slope(0.0)
    j1 = AXIS1 @ i1 @ AXIS1 + M_1 * np.sum(np.cross(AXIS1, r1) ** 2)
    j2 = AXIS2 @ i2 @ AXIS2 + M_2 * np.sum(np.cross(AXIS2, r2) ** 2)
    return np.sqrt(v2 / (j1 + j2 * dth2 ** 2)), potential, h


def test_spatial_loop_under_gravity_second_formulation():
    omega, potential, h = _spatial_second_formulation()
    # the reference is an equilibrium, and the loop really is preloaded (crank 2 alone would
    # tip): V'(0) = 0 while the gravity moment of crank 2 about its axis is not zero
    assert abs(potential(h) - potential(-h)) / (2 * h) < 1e-6
    data = _spatial_dict()
    r2 = np.array(data["bodies"]["crank2"]["com"]) - O2
    assert abs(np.cross(AXIS2, r2)[2]) > 0.02
    np.testing.assert_allclose(_frequency(vehicle_from_dict(data)), omega, rtol=1e-6)


def test_spatial_loop_curvature_term_is_large_enough_to_be_seen():
    """The loop's curvature term m2 g (dz2/dth2) th2''(0) is about 10 % of V''(0): an engine
    that dropped the constraint bias or the Jacobian's derivative would miss the 1e-6 check
    above by far."""
    _, potential, h = _spatial_second_formulation()

    def slope(th1):
        return (_theta2(th1 + 1e-20j)).imag / 1e-20

    curvature = (slope(1e-5) - slope(-1e-5)) / 2e-5
    r2 = np.array(_spatial_dict()["bodies"]["crank2"]["com"]) - O2
    term = M_2 * G * np.cross(AXIS2, r2)[2] * curvature
    v2 = (potential(h) - 2 * potential(0.0) + potential(-h)) / h ** 2
    assert abs(term / v2) > 0.05


# --- bad input ---------------------------------------------------------------------------------

def test_loop_that_cannot_close_names_file_and_joint():
    o, b, c, d = _four_bar_points()
    data = _four_bar_dict(closing_pin={"child_point": (c + [0.0015, 0, 0]).tolist()})
    with pytest.raises(ConfigError) as err:
        vehicle_from_dict(data, "four_bar.yaml")
    message = str(err.value)
    assert "four_bar.yaml" in message and "joints.closing_pin.child_point" in message
    assert "1.5 mm" in message and "cannot close" in message


def test_loop_within_tolerance_is_accepted():
    o, b, c, d = _four_bar_points()
    data = _four_bar_dict(closing_pin={"child_point": (c + [0.0005, 0, 0]).tolist()})
    assert build_system(vehicle_from_dict(data))


def test_redundant_planar_loop_of_four_revolutes_refused():
    """Four revolute joints with parallel axes: the loop's out-of-plane equations are
    redundant (Gruebler: -2 degrees of freedom, really 1): refused, naming the cut joint."""
    data = _four_bar_dict(coupler_pin={"type": "revolute", "axis2": None},
                          closing_pin={"type": "revolute", "axis": [0, 0, 1]})
    data["joints"]["coupler_pin"].pop("axis2")
    with pytest.raises(ConfigError) as err:
        build_system(vehicle_from_dict(data, "four_bar.yaml"))
    message = str(err.value)
    assert "four_bar.yaml" in message and "redundant" in message and "closing_pin" in message


def test_over_constrained_loop_refused():
    """A fixed cut joint on a four-bar: six equations on three loop coordinates."""
    data = _four_bar_dict(closing_pin={"type": "fixed"})
    with pytest.raises(ConfigError) as err:
        build_system(vehicle_from_dict(data, "four_bar.yaml"))
    assert "over-constrained" in str(err.value) and "closing_pin" in str(err.value)


def test_joint_naming_a_missing_body_names_file_and_joint():
    data = _four_bar_dict(closing_pin={"child": "rokcer"})
    with pytest.raises(ConfigError) as err:
        vehicle_from_dict(data, "four_bar.yaml")
    assert "four_bar.yaml" in str(err.value) and "joints.closing_pin.child" in str(err.value)
    assert "rokcer" in str(err.value)


@pytest.mark.parametrize("override, key", [
    ({"type": "spherical", "locked": True}, "joints.coupler_pin.locked"),
    ({"axis2": [0.0, 0.0, 2.0]}, "joints.coupler_pin.axis2"),
])
def test_bad_joint_keys_name_file_and_key(override, key):
    data = _four_bar_dict(coupler_pin=override)
    with pytest.raises(ConfigError) as err:
        vehicle_from_dict(data, "four_bar.yaml")
    assert "four_bar.yaml" in str(err.value) and key in str(err.value)


def test_fixed_base_refuses_wheels():
    data = _four_bar_dict()
    data["wheels"] = {"w": {}}
    with pytest.raises(ConfigError) as err:
        vehicle_from_dict(data, "four_bar.yaml")
    assert "wheels" in str(err.value)


def test_joint_joining_a_body_to_itself_refused():
    data = _four_bar_dict(closing_pin={"child": "coupler"})
    with pytest.raises((ConfigError, ModelError)) as err:
        vehicle_from_dict(data, "four_bar.yaml")
    assert "closing_pin" in str(err.value)
