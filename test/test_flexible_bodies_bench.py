"""The paper's flexible bodies joined in the engine (issue 12, Appendix and Table A.1).

Each shipped beam component is built on the bench IN THE ENGINE from its per-body
superelements (several ends each), bushings (its springs) and spherical cut joints (its
translation links), clamps welded to the ground (:func:`bench_model`), and checked against a
second formulation: the component-mode synthesis by transformation of
:func:`~motoflex_ros.structures.bodies.assemble_bodies` (same reduced bodies).

- Frequencies: every undamped natural frequency equal to 1e-8 relative (both models span the
  same space; the engine reaches it by chains, loops and complex-step linearization).
- Static: the loaded end's 6 x 6 compliance (a wrench on the engine body that moves with the
  loaded end) equal to 1e-8 relative.
- The same count of independent coordinates as the synthesis (a bushing closed by a cut joint
  has all its coordinates solved from the loop, the zero-stiffness directions of the slider
  bushings and of the ball joints included).
- Two ways to carry a body that holds no clamp: a free rigid body on six joints from the
  ground, or the rigid body carried by the bushing of the spring that joins it to the bodies
  placed before it (its rigid coordinates are then the bushing's).
- The check can fail: dropping the elastic-rigid coupling M_xR moves the frequencies.
- Analytic: a cantilever with two ends whose tip is pinned to the ground by a spherical cut
  joint gives the clamped-pinned beam of the full FE model (all fixed-interface modes kept) to
  1e-6, and the Craig-Bampton model with the same constraint to 1e-9 (four modes kept); a rigid
  block on three ball-joint bushings (zero rotational stiffness, determined by the loop) gives
  eig(sum G^T K6 G, M) and C = beta K; a free direction without mass is a ModelError naming
  the bushing.
"""
import time
from dataclasses import replace

import numpy as np
import pytest
import scipy.linalg as sla

from motoflex_ros.config import MOTORCYCLE_COMPONENTS
from motoflex_ros.errors import ModelError
from motoflex_ros.formats.component_file import load_component
from motoflex_ros.spatial import skew
from motoflex_ros.structures.assembly import Structure, rigid_body_mass
from motoflex_ros.structures.beam import Material, tube_section
from motoflex_ros.structures.bodies import assemble_bodies, reduce_bodies
from motoflex_ros.structures.component_model import Component
from motoflex_ros.vehicle.dynamics import build_system
from motoflex_ros.vehicle.flexible_bodies import (
    bench_model,
    body_elements,
    point_jacobian,
    stiffness_damping_factor,
)
from motoflex_ros.vehicle.linearize import linearize_at, mechanism_matrices
from motoflex_ros.vehicle.model import Body, Joint, VehicleModel
from motoflex_ros.vehicle.superelement import bushing, chain_parts, end_body

EQUAL = 1e-8


def _frequencies_hz(M, K):
    return np.sqrt(np.maximum(sla.eigh(K, M, eigvals_only=True), 0.0)) / (2 * np.pi)


# the front assembly only carried (as the vehicle builds it): its free form (six joints per
# body, 162 coordinates) costs 10-30 s and proves nothing the frame and swingarm do not
@pytest.fixture(scope="module", params=[(name, carry) for name in MOTORCYCLE_COMPONENTS
                                        for carry in (False, True)
                                        if carry or name != "front_assembly"],
                ids=lambda p: f"{p[0]}-{'carried' if p[1] else 'free'}")
def bench(request):
    """The component on the bench; free bodies on six joints from the ground, or carried by
    the spring that joins them to the bodies placed before (``carry``)."""
    name, carry = request.param
    component = load_component(name)
    bodies = reduce_bodies(component)
    model, built = bench_model(component, bodies, carry=carry)
    system = build_system(model)
    start = time.perf_counter()
    M, C, K = mechanism_matrices(system)
    seconds = time.perf_counter() - start
    return component, bodies, assemble_bodies(component, bodies), system, built, (M, C, K), \
        seconds


def test_bench_frequencies_are_the_synthesis(bench):
    component, _, assembly, system, _, (M, _, K), seconds = bench
    engine = _frequencies_hz(M, K)
    synthesis = assembly.frequencies_hz()
    assert len(engine) == len(synthesis)
    error = np.max(np.abs(engine - synthesis) / synthesis)
    print(f"{component.name}: {len(engine)} independent coordinates of "
          f"{len(system.tree.coordinates)}, max relative frequency difference {error:.2e}, "
          f"linearization {seconds:.2f} s")
    assert error <= EQUAL


def test_bench_loaded_end_compliance_is_the_synthesis(bench):
    component, _, assembly, system, built, (_, _, K), _ = bench
    end = next(n for n, i in component.node_names.items() if i == component.loaded_end)
    jac = point_jacobian(system, built.node_bodies[end], component.origin + component.q0)
    engine = jac @ np.linalg.solve(K, jac.T)
    synthesis = assembly.static_compliance(component.loaded_end)
    error = np.max(np.abs(engine - synthesis)) / np.max(np.abs(synthesis))
    print(f"{component.name}: max relative compliance difference {error:.2e}")
    assert error <= EQUAL


def test_bushings_are_solved_from_their_loops(bench):
    _, _, _, system, built, _, _ = bench
    names = [c.name for c in system.tree.coordinates]
    dependent = {names[k] for k in system.loop_dep}
    closed = {j.parent for j in built.joints if j.cut and j.kind == "fixed"}
    for element in built.bushings:
        if end_body(element) not in closed:
            continue        # carries a rigid body: its coordinates are that body's
        prefix = element.name + "_"
        own = [n for n in names if n.startswith(prefix) and n[len(prefix):] in
               ("ux", "uy", "uz", "rx", "ry", "rz")]
        assert len(own) == 6 and set(own) <= dependent


def test_bench_damping_is_stiffness_proportional(bench):
    component, bodies, _, _, built, (M, C, K), _ = bench
    beta = stiffness_damping_factor(component, bodies)
    assert built.beta == pytest.approx(beta)
    # the first clamped mode gets the component's damping ratio (phi mass-normalised)
    w2, phi = sla.eigh(K, M)
    c1 = phi[:, 0] @ C @ phi[:, 0]
    assert c1 / (2 * np.sqrt(w2[0])) == pytest.approx(component.damping_ratio, rel=1e-7)
    np.testing.assert_allclose(C, beta * K, rtol=0, atol=1e-9 * beta * np.max(np.abs(K)))


def test_dropping_the_coupling_moves_the_frequencies():
    """The frequency check can fail: without M_xR the bodies' elastic coordinates do not feel
    their carriers' motion and the frequencies leave the synthesis's by far more than 1e-8."""
    component = load_component("swingarm")
    bodies = reduce_bodies(component)
    model, built = bench_model(component, bodies)
    cut = tuple(replace(e, couplings=tuple((b, 0 * m) for b, m in e.couplings))
                for e in model.elements)
    M, _, K = mechanism_matrices(build_system(replace(model, elements=cut)))
    synthesis = assemble_bodies(component, bodies).frequencies_hz()
    assert np.max(np.abs(_frequencies_hz(M, K) - synthesis) / synthesis) > 1e-3


# --- analytic: a cantilever with two ends, its tip pinned --------------------------------------

LENGTH = 0.8                       # [m]
STEEL = Material(2.1e11, 8.1e10, 7850.0)
TUBE = tube_section(0.030, 0.003)


def _cantilever():
    s = Structure()
    root = s.add_node([0.0, 0.0, 0.0])
    mid = s.add_node([LENGTH / 2, 0.0, 0.0])
    tip = s.add_node([LENGTH, 0.0, 0.0])
    s.add_member(root, mid, 6, TUBE, STEEL, up=[0.0, 1.0, 0.0])
    s.add_member(mid, tip, 6, TUBE, STEEL, up=[0.0, 1.0, 0.0])
    return Component(name="cantilever", structure=s, clamp_nodes=(root,), loaded_end=tip,
                     interface_nodes=(root, tip, mid),
                     node_names={"root": root, "mid": mid, "tip": tip},
                     origin=np.array([0.1, 0.2, 0.3]), source="cantilever")


def _pinned_engine_frequencies(component, bodies):
    (body,) = bodies
    built = body_elements(component, bodies, {body.name: ("ground", "root")},
                          welds={"root": "ground"})
    tip = component.origin + component.q0
    pin = Joint("pin", "spherical", "ground", built.node_bodies["tip"], np.eye(3)[0], tip,
                axis2=np.eye(3)[1], cut=True)
    model = VehicleModel("pinned", "pinned cantilever", 0.0, "ground",
                         (Body("ground", 0.0, np.zeros(3), np.zeros((3, 3))),) + built.bodies,
                         built.joints + (pin,), (), elements=built.elements, base="fixed")
    system = build_system(model)
    M, _, K = mechanism_matrices(system)
    return _frequencies_hz(M, K), system


def _full_clamped_pinned():
    component = _cantilever()
    s = component.structure
    ground = s.add_node([LENGTH, 0.0, 0.0])
    s.clamp(ground)
    s.clamp(component.clamp_nodes[0])
    s.add_link(ground, component.loaded_end, (0, 1, 2))
    asm = s.assemble()
    return _frequencies_hz(asm.M.toarray(), asm.K.toarray())


def test_pinned_cantilever_is_the_full_clamped_pinned_beam():
    component = _cantilever()
    bodies = reduce_bodies(component, n_modes=10_000, f_max_hz=1e12)   # every interior mode
    engine, system = _pinned_engine_frequencies(component, bodies)
    full = _full_clamped_pinned()
    assert len(engine) == len(full)
    print(f"pinned cantilever: first frequency {engine[0]:.6f} Hz, full FE {full[0]:.6f} Hz, "
          f"relative difference {abs(engine[0] / full[0] - 1):.2e}")
    assert engine[0] == pytest.approx(full[0], rel=1e-6)
    # and the beam is the clamped-pinned one (Euler-Bernoulli: beta L = 3.9266; Timoshenko
    # shear and rotary inertia put it about 1 % below at L/D = 27), not the clamped-free
    # beam (beta L = 1.8751, 4.4 times lower)
    ei, rho_a = STEEL.E * TUBE.Iy, STEEL.rho * TUBE.A
    euler = 3.92660231 ** 2 / (2 * np.pi * LENGTH ** 2) * np.sqrt(ei / rho_a)
    assert 0.97 * euler < engine[0] < euler
    # the tip's end chain holds the body; the pin makes three of its coordinates dependent
    names = [system.tree.coordinates[k].name for k in system.loop_dep]
    assert sorted(names) == ["cantilever_root_tip_ux", "cantilever_root_tip_uy",
                             "cantilever_root_tip_uz"]


def test_pinned_cantilever_is_the_craig_bampton_model_pinned():
    component = _cantilever()
    bodies = reduce_bodies(component, n_modes=4, f_max_hz=1e12)
    (body,) = bodies
    engine, _ = _pinned_engine_frequencies(component, bodies)
    # the same reduced body, root DOFs and tip translations removed by hand
    tip = list(body.boundary).index(component.loaded_end)
    root = list(body.boundary).index(component.clamp_nodes[0])
    drop = set(range(6 * root, 6 * root + 6)) | set(range(6 * tip, 6 * tip + 3))
    keep = [i for i in range(body.n) if i not in drop]
    cb = _frequencies_hz(body.M[np.ix_(keep, keep)], body.K[np.ix_(keep, keep)])
    np.testing.assert_allclose(engine, cb, rtol=1e-9)


# --- bushings: zero-stiffness directions in a loop, and a free one -----------------------------

POINTS = np.array([[0.0, 0.0, 0.0], [0.4, 0.1, 0.0], [0.1, 0.3, 0.2]])
K_BALL = np.diag([2.0e6, 3.0e6, 4.0e6, 0.0, 0.0, 0.0])    # ball joint: rotations free
MASS, COM, INERTIA = 5.0, np.array([0.2, 0.15, 0.1]), np.diag([0.05, 0.06, 0.07])
BETA = 1e-4                                               # [s]


def _free_block(joints):
    """A rigid block on six joints from the ground (x, y, z, then rotations through POINTS[0])."""
    bodies, parent = [], "ground"
    for i in range(6):
        child = "block" if i == 5 else f"block_free{i}"
        bodies.append(Body(child, MASS if i == 5 else 0.0, COM if i == 5 else POINTS[0],
                           INERTIA if i == 5 else np.zeros((3, 3))))
        joints.append(Joint(f"block_{i}", "prismatic" if i < 3 else "revolute", parent, child,
                            np.eye(3)[i % 3], POINTS[0]))
        parent = child
    return bodies


def test_ball_joint_bushings_in_a_loop():
    """Three ball-joint bushings (no rotational stiffness) hold a rigid block: their rotation
    coordinates are solved from the loops, and the block's frequencies are those of
    K = sum G_i^T K6 G_i, M the block's rigid mass (coordinates: translation at POINTS[0] and
    rotation), C = beta K."""
    joints = []
    bodies = [Body("ground", 0.0, np.zeros(3), np.zeros((3, 3)))] + _free_block(joints)
    elements = []
    for i, p in enumerate(POINTS):
        b = bushing(f"ball{i}", "ground", p, K_BALL, BETA * K_BALL)
        parts = chain_parts(b)
        bodies += parts[0]
        joints += parts[1] + [Joint(f"ball{i}_close", "fixed", end_body(b), "block",
                                    np.eye(3)[0], p, cut=True)]
        elements.append(b)
    model = VehicleModel("block", "block on bushings", 0.0, "ground", tuple(bodies),
                         tuple(joints), (), elements=tuple(elements), base="fixed")
    system = build_system(model)
    assert len(system.indep_pos) == 6
    M, C, K = mechanism_matrices(system)
    k_want = np.zeros((6, 6))
    for p in POINTS:
        g = np.eye(6)
        g[:3, 3:] = -skew(p - POINTS[0])
        k_want += g.T @ K_BALL @ g
    m_want = rigid_body_mass(MASS, INERTIA, COM - POINTS[0])
    np.testing.assert_allclose(_frequencies_hz(M, K), _frequencies_hz(m_want, k_want),
                               rtol=1e-9)
    np.testing.assert_allclose(C, BETA * K, rtol=0, atol=1e-12 * BETA * np.max(np.abs(K)))


def test_free_massless_direction_is_a_model_error():
    """A bushing whose end body carries nothing is allowed while every direction has stiffness
    (massless coordinates, infinite eigenvalues); one free direction is undetermined: a
    ModelError naming the bushing, not a singular matrix."""
    ground = Body("ground", 0.0, np.zeros(3), np.zeros((3, 3)))
    for stiffness, fails in ((np.diag([1e6] * 3 + [1e3] * 3), False), (K_BALL, True)):
        b = bushing("dangling", "ground", POINTS[1], stiffness)
        parts = chain_parts(b)
        model = VehicleModel("dangling", "dangling bushing", 0.0, "ground",
                             (ground,) + tuple(parts[0]), tuple(parts[1]), (), elements=(b,),
                             base="fixed")
        system = build_system(model)
        if fails:
            with pytest.raises(ModelError, match="'dangling'.*neither mass nor stiffness"):
                linearize_at(system, 0.0)
        else:
            E, _ = linearize_at(system, 0.0)
            assert not np.any(E[6:, 6:])
