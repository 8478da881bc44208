"""Independent second formulation of the rigid touring motorcycle on linear tyres.

A different code path from motoflex_ros.vehicle: sympy.physics.mechanics derives, with Kane's
method, the unconstrained mass matrix and forcing of the vehicle in heading-frame quasi-speeds,
every part of the frame body as its own rigid body (so the parallel-axis combination is checked
too), the toroidal contact point (crown radius), the rolling-constraint Jacobian and its time
derivative by symbolic differentiation, the tyre force and moment (Magic Formula linearized at
wheel loads this file computes from the YAML by moment balance, not at the engine's static
loads), the rider lean spring/damper
and the steering damper. Numerically: contact heights by Newton, dependent speeds from the
constraints, accelerations from the saddle-point (KKT) system with multipliers (not partial
velocities), relaxation equations divided by sigma(v), linearization by complex step. The
eigenvalues must equal the engine's at three speeds to 1e-6 relative (issue 5).
"""
import numpy as np
import pytest
import yaml

sm = pytest.importorskip("sympy")
me = pytest.importorskip("sympy.physics.mechanics")

from test_vehicle_mass_published import (  # noqa: E402
    moment_balance_loads,
    yaml_centre_of_mass,
)

from motoflex_ros.config import config_path  # noqa: E402
from motoflex_ros.vehicle.linearize import linearize  # noqa: E402
from motoflex_ros.vehicle.model import vehicle_from_dict  # noqa: E402
from motoflex_ros.vehicle.tyre import tyre_from_config  # noqa: E402

H = 1e-30


def _inertia_dyadic(frame, spec):
    return me.inertia(frame, spec["xx"], spec["yy"], spec["zz"], spec.get("xy", 0.0),
                      spec.get("yz", 0.0), spec.get("xz", 0.0))


def _rigid(name, frame, origin, ref_point, spec, bodies, gravity, loads, N):
    """A rigid body whose reference com is spec['com'], fixed in ``frame`` that passes through
    ``origin`` (a point whose reference position is ref_point)."""
    offset = [c - r for c, r in zip(spec["com"], ref_point)]
    com = origin.locatenew(f"{name}_com", sum((o * e for o, e in zip(offset, frame)),
                                              0 * frame.x))
    com.v2pt_theory(origin, N, frame)
    bodies.append(me.RigidBody(name, com, frame, spec["mass"],
                               (_inertia_dyadic(frame, spec["inertia"]), com)))
    loads.append((com, -spec["mass"] * gravity * N.z))


def _vec(frame, components):
    return sum((c * e for c, e in zip(components, frame)), 0 * frame.x)


def _unit(vector):
    return vector / sm.sqrt(vector.dot(vector))


class KaneMotorcycle:
    """Symbolic touring motorcycle: config/vehicles/touring.yaml with its mechanisms frozen
    (a revolute steering joint through the head point along the steering axis)."""

    def __init__(self, data, tyres):
        self.data = data
        q = me.dynamicsymbols("x y z psi phi theta delta beta thr thf")
        u = me.dynamicsymbols("ufwd ulat uz upsi uphi utheta udelta ubeta uthr uthf")
        self.q, self.u = q, u
        self.tyre_states = sm.symbols("F_f M_f F_r M_r")
        N = me.ReferenceFrame("N")
        A = N.orientnew("A", "Axis", [q[3], N.z])
        B = A.orientnew("B", "Axis", [q[4], A.x])
        C = B.orientnew("C", "Axis", [q[5], B.y])
        C.set_ang_vel(N, u[3] * N.z + u[4] * A.x + u[5] * B.y)
        O = me.Point("O")
        O.set_vel(N, 0)
        P0 = O.locatenew("P0", q[0] * N.x + q[1] * N.y + q[2] * N.z)
        P0.set_vel(N, u[0] * A.x + u[1] * A.y + u[2] * N.z)
        self.kd = [q[0].diff() - (u[0] * sm.cos(q[3]) - u[1] * sm.sin(q[3])),
                   q[1].diff() - (u[0] * sm.sin(q[3]) + u[1] * sm.cos(q[3]))]
        self.kd += [qi.diff() - ui for qi, ui in zip(q[2:], u[2:])]
        self.N, self.C, self.P0 = N, C, P0
        self.bodies, self.loads = [], []
        self._build(data, tyres)

    def _build(self, data, tyres):
        N, C, P0, q, u = self.N, self.C, self.P0, self.q, self.u
        g = data["gravity"]
        zero = [0.0, 0.0, 0.0]
        for name, part in data["bodies"]["frame"]["parts"].items():
            _rigid(name, C, P0, zero, part, self.bodies, g, self.loads, N)
        # the frozen Paralever and the Telelever's longitudinal arm ride with the rear frame:
        # this oracle is the tree the locked mechanism reduces to (steering about the axis
        # through the two spherical joints), so comparing it with the engine also checks the
        # engine's loop closures
        for name in ("swingarm", "torque_strut", "wheel_carrier", "telelever_arm"):
            if name in data["bodies"]:
                _rigid(name, C, P0, zero, data["bodies"][name], self.bodies, g, self.loads, N)
        lean, steer = data["joints"]["rider_lean"], data["joints"]["steer"]
        F = C.orientnew("F", "Axis", [q[7], _vec(C, lean["axis"])])
        F.set_ang_vel(C, u[7] * _vec(C, lean["axis"]))
        hip = P0.locatenew("hip", _vec(C, lean["point"]))
        hip.v2pt_theory(P0, N, C)
        _rigid("rider", F, hip, lean["point"], data["bodies"]["rider_upper_body"], self.bodies,
               g, self.loads, N)
        axis = np.array(steer["axis"]) / np.linalg.norm(steer["axis"])
        D = C.orientnew("D", "Axis", [q[6], _vec(C, axis)])
        D.set_ang_vel(C, u[6] * _vec(C, axis))
        S = P0.locatenew("S", _vec(C, steer["point"]))
        S.v2pt_theory(P0, N, C)
        for name in ("upper_fork", "lower_fork"):
            _rigid(name, D, S, steer["point"], data["bodies"][name], self.bodies, g, self.loads,
                   N)
        torque_lean = -(lean["stiffness"] * q[7] + lean["damping"] * u[7]) * _vec(C, lean["axis"])
        torque_steer = -steer["damping"] * u[6] * _vec(C, axis)
        self.loads += [(F, torque_lean), (C, -torque_lean), (D, torque_steer),
                       (C, -torque_steer)]
        self.contacts = [self._wheel("front", D, S, steer["point"], q[9], u[9], tyres[0],
                                     self.tyre_states[:2]),
                         self._wheel("rear", C, P0, [0.0, 0.0, 0.0], q[8], u[8], tyres[1],
                                     self.tyre_states[2:])]

    def _wheel(self, name, carrier, origin, ref_point, angle, rate, tyre, forces):
        N = self.N
        w = self.data["wheels"][name]
        Wf = carrier.orientnew(f"{name}_wheel", "Axis", [angle, carrier.y])
        Wf.set_ang_vel(carrier, rate * carrier.y)
        centre = origin.locatenew(f"{name}_centre",
                                  _vec(carrier, [c - r for c, r in zip(w["centre"], ref_point)]))
        centre.v2pt_theory(origin, N, carrier)
        mass = w["mass"]
        inertia = me.inertia(Wf, w["inertia"]["diametral"], w["inertia"]["spin"],
                             w["inertia"]["diametral"])
        self.bodies.append(me.RigidBody(f"{name}_wheel", centre, Wf, mass, (inertia, centre)))
        self.loads.append((centre, -mass * self.data["gravity"] * N.z))
        a = Wf.y
        d = -N.z
        e = _unit(d - d.dot(a) * a)
        rho = (w["radius"] - w["crown_radius"]) * e + w["crown_radius"] * d
        contact = centre.locatenew(f"{name}_contact", rho)
        v_material = centre.vel(N) + Wf.ang_vel_in(N).cross(rho)
        contact.set_vel(N, v_material)
        t = _unit(a.cross(N.z))
        lateral = N.z.cross(t)
        side, moment = forces
        self.loads += [(contact, side * lateral), (Wf, moment * N.z)]
        return {"height": centre.pos_from(self.P0).dot(N.z) + self.q[2] + rho.dot(N.z),
                "long": t.dot(v_material), "normal": N.z.dot(v_material),
                "slip": lateral.dot(v_material), "camber": -sm.asin(a.dot(N.z)), "tyre": tyre}

    def numeric(self):
        """Lambdified M(q), f(q, u, z), G(q), b(q, u), heights, slips and cambers.

        The dynamic symbols are replaced by plain ones (``xreplace``: none of the expressions
        holds a coordinate rate) before anything is differentiated or compiled: sympy
        differentiates plain symbols several times faster than functions of time, and
        ``msubs`` walking the whole tree took a third of this fixture."""
        kane = me.KanesMethod(self.N, q_ind=self.q, u_ind=self.u, kd_eqs=self.kd)
        kane.kanes_equations(self.bodies, self.loads)
        qs, us = sm.symbols("q0:10"), sm.symbols("u0:10")
        sub = dict(zip(self.q, qs)) | dict(zip(self.u, us))
        plain = lambda expr: expr.xreplace(sub)  # noqa: E731
        rows = sm.Matrix([plain(c[k]) for c in self.contacts for k in ("long", "normal")])
        G = rows.jacobian(us)
        rates = sm.solve(self.kd, [qi.diff() for qi in self.q])
        qdot = [plain(rates[qi.diff()]) for qi in self.q]
        bias = sm.Matrix([sum(sm.diff(r, qi) * qd for qi, qd in zip(qs, qdot))
                          for r in G * sm.Matrix(us)])
        forcing = kane.forcing   # already in speeds: no coordinate rates left
        assert not forcing.has(*[qi.diff() for qi in self.q])
        heights = sm.Matrix([plain(c["height"]) for c in self.contacts])
        exprs = {"M": plain(kane.mass_matrix), "f": plain(forcing), "G": G, "b": bias,
                 "h": heights, "dh": heights.jacobian([qs[2], qs[5]])}
        assert not any(e.has(*self.q, *self.u, sm.Derivative) for e in exprs.values())
        # common subexpressions in the order found (sympy's canonical ordering of them is
        # what makes the default slow); list=False keeps a Matrix a Matrix
        cse = lambda expr: sm.cse(expr, order="none", list=False)  # noqa: E731
        args = {"M": [qs], "f": [qs, us, self.tyre_states], "G": [qs], "b": [qs, us],
                "h": [qs], "dh": [qs]}
        fns = {name: sm.lambdify(args[name], expr, cse=cse) for name, expr in exprs.items()}
        fns["slip"] = sm.lambdify([qs, us], [plain(c["slip"]) for c in self.contacts], cse=cse)
        fns["camber"] = sm.lambdify([qs], [plain(c["camber"]) for c in self.contacts], cse=cse)
        return fns


IND_Q = (4, 6, 7)            # roll, steer, rider lean
IND_U = (1, 3, 4, 6, 7)      # lateral speed, yaw, roll, steer, lean rates
DEP_U = (2, 5, 8, 9)         # z', pitch', rear spin, front spin


def _state_derivative(fns, tyres, x, v):
    dtype = x.dtype
    q = np.zeros(10, dtype)
    q[list(IND_Q)] = x[:3]
    for _ in range(3):
        dep = np.array([q[2], q[5]]) - np.linalg.solve(np.array(fns["dh"](q), dtype),
                                                       np.ravel(fns["h"](q)))
        q[2], q[5] = dep
    u = np.zeros(10, dtype)
    u[0] = v
    u[list(IND_U)] = x[3:8]
    G = np.array(fns["G"](q), dtype)
    u[list(DEP_U)] = np.linalg.solve(G[:, list(DEP_U)], -G @ u)
    z = x[8:]
    M = np.array(fns["M"](q), dtype)
    kkt = np.block([[M, G.T], [G, np.zeros((4, 4))]])
    rhs = np.concatenate([np.ravel(fns["f"](q, u, z)), -np.ravel(fns["b"](q, u))])
    udot = np.linalg.solve(kkt, rhs)[:10]
    slips, cambers = fns["slip"](q, u), fns["camber"](q)
    zdot = []
    for k, tyre in enumerate(tyres):
        sigma = tyre.relaxation_length(v)
        F, Mz = z[2 * k], z[2 * k + 1]
        zdot.append((-tyre.k_alpha * slips[k] + v * (tyre.k_gamma * cambers[k] - F)) / sigma)
        zdot.append((tyre.k_malpha * slips[k] + v * (tyre.k_mgamma * cambers[k] - Mz)) / sigma)
    return np.concatenate([u[list(IND_Q)], udot[list(IND_U)], np.array(zdot, dtype)])


def _state_matrix(fns, tyres, v):
    n = 12
    A = np.zeros((n, n))
    for k in range(n):
        x = np.zeros(n, complex)
        x[k] = 1j * H
        A[:, k] = _state_derivative(fns, tyres, x, v).imag / H
    return A


@pytest.fixture(scope="module")
def touring_data():
    with open(config_path("vehicles", "touring"), encoding="utf-8") as stream:
        return yaml.safe_load(stream)


def oracle_tyres(data):
    """Front and rear linear tyres: the Magic Formula linearized at the wheel loads computed
    here from the YAML (moment balance about the contact points), not at the engine's."""
    mass, com = yaml_centre_of_mass(data)
    loads = moment_balance_loads(data, mass, com)
    return tuple(tyre_from_config(data["wheels"][name]["tyre"], "touring", f"{name}.tyre", fz,
                                  data["wheels"][name]["crown_radius"])
                 for name, fz in zip(("front", "rear"), loads))


@pytest.fixture(scope="module")
def oracle(touring_data):
    engine = linearize(vehicle_from_dict(touring_data, "touring"))
    tyres = oracle_tyres(touring_data)
    model = KaneMotorcycle(touring_data, tyres)
    return engine, model.numeric(), tyres


@pytest.mark.parametrize("kmh", [50.0, 120.0, 200.0])
def test_touring_eigenvalues_second_formulation(oracle, kmh):
    engine, fns, tyres = oracle
    v = kmh / 3.6
    want = engine.eigenvalues(v)
    got = np.linalg.eigvals(_state_matrix(fns, tyres, v))
    assert len(got) == len(want)
    for z in want:
        assert np.min(np.abs(got - z)) <= 1e-6 * abs(z), (z, got)
