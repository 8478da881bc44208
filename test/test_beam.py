"""Timoshenko beam element against closed-form cantilever solutions.

References: static cantilever with shear, delta = F L^3/(3 E I) + F L/(G A_s), section rotation
F L^2/(2 E I); twist T L/(G J); clamped-free Timoshenko beam frequency equation of Huang (1961),
J. Appl. Mech. 28, 579-584 (as written in Han, Benaroya & Wei, J. Sound Vib. 225, 1999,
eq. for the clamped-free beam); uniform shaft torsion f = (1/4L) sqrt(G J / (rho I_p)) and, for
linear elements with consistent mass, the discrete dispersion of a uniform rod (e.g. Hughes,
The Finite Element Method, 1987, sect. 9.2).
"""
import numpy as np
import pytest
import scipy.linalg as sla
from scipy.optimize import brentq

from motoflex_ros.structures.assembly import Structure
from motoflex_ros.structures.beam import Material, rectangular_tube_section, tube_section
from motoflex_ros.structures.component_model import tube_component

STEEL = Material(E=2.1e11, G=8.1e10, rho=7850.0)
LENGTH, DIAMETER, WALL = 0.6, 0.04, 0.002


def _cantilever(section, count, pitch_deg=0.0):
    pitch = np.radians(pitch_deg)
    s = Structure()
    root = s.add_node([0, 0, 0])
    tip = s.add_node(LENGTH * np.array([np.cos(pitch), 0.0, np.sin(pitch)]))
    s.add_member(root, tip, count, section, STEEL, up=(0.0, 1.0, 0.0))
    s.clamp(root)
    return s, tip


def _tip_motion(section, count, load):
    s, tip = _cantilever(section, count)
    asm = s.assemble()
    f = np.zeros(asm.K.shape[0])
    f[asm.node_dofs(tip)] = load
    u = sla.solve(asm.K.toarray(), f)
    return u[asm.node_dofs(tip)]


@pytest.mark.parametrize("count", [1, 4])
def test_cantilever_tip_deflection_and_slope_analytic(count):
    """Both bending planes, with shear; a rectangular tube makes the planes differ."""
    sec = rectangular_tube_section(width=0.03, height=0.05, wall_thickness=0.002)
    force = 1000.0
    lateral = _tip_motion(sec, count, [0, force, 0, 0, 0, 0])
    delta_y = force * LENGTH**3 / (3 * STEEL.E * sec.Iz) + force * LENGTH / (STEEL.G * sec.A_sy)
    assert lateral[1] == pytest.approx(delta_y, rel=1e-10)
    assert lateral[5] == pytest.approx(force * LENGTH**2 / (2 * STEEL.E * sec.Iz), rel=1e-10)
    vertical = _tip_motion(sec, count, [0, 0, force, 0, 0, 0])
    delta_z = force * LENGTH**3 / (3 * STEEL.E * sec.Iy) + force * LENGTH / (STEEL.G * sec.A_sz)
    assert vertical[2] == pytest.approx(delta_z, rel=1e-10)
    assert vertical[4] == pytest.approx(-force * LENGTH**2 / (2 * STEEL.E * sec.Iy), rel=1e-10)
    assert abs(delta_y / delta_z - 1) > 0.5   # the two planes really differ


def test_twist_under_end_torque_analytic():
    sec = tube_section(DIAMETER, WALL)
    torque = 50.0
    motion = _tip_motion(sec, 3, [0, 0, 0, torque, 0, 0])
    assert motion[3] == pytest.approx(torque * LENGTH / (STEEL.G * sec.J), rel=1e-10)


def test_total_mass_of_rigid_translation_analytic():
    sec = tube_section(DIAMETER, WALL)
    s, _ = _cantilever(sec, 7, pitch_deg=30.0)
    s.clamped.clear()
    asm = s.assemble()
    for axis in range(3):
        e = np.zeros(asm.M.shape[0])
        e[axis::6] = 1.0
        assert e @ (asm.M @ e) == pytest.approx(STEEL.rho * sec.A * LENGTH, rel=1e-12)


def _huang_clamped_free(omega, sec):
    """Huang's frequency equation of a clamped-free Timoshenko beam (zero at eigenvalues)."""
    b2 = STEEL.rho * sec.A * LENGTH**4 * omega**2 / (STEEL.E * sec.Iy)
    b = np.sqrt(b2)
    r2 = sec.Iy / (sec.A * LENGTH**2)
    s2 = STEEL.E * sec.Iy / (sec.A_sy * STEEL.G * LENGTH**2)
    root = np.sqrt((r2 - s2) ** 2 + 4 / b2)
    alpha = np.sqrt((-(r2 + s2) + root) / 2)
    beta = np.sqrt(((r2 + s2) + root) / 2)
    return (2 + (b2 * (r2 - s2) ** 2 + 2) * np.cosh(b * alpha) * np.cos(b * beta)
            - b * (r2 + s2) / np.sqrt(1 - b2 * r2 * s2) * np.sinh(b * alpha) * np.sin(b * beta))


def _first_bending_hz(sec):
    omegas = np.linspace(2 * np.pi * 20, 2 * np.pi * 400, 400)
    vals = np.array([_huang_clamped_free(w, sec) for w in omegas])
    i = np.flatnonzero(np.sign(vals[:-1]) != np.sign(vals[1:]))[0]
    return brentq(_huang_clamped_free, omegas[i], omegas[i + 1], args=(sec,)) / (2 * np.pi)


def _clamped_frequencies(count, pitch_deg=0.0):
    comp = tube_component(LENGTH, DIAMETER, WALL, pitch_deg, STEEL, count)
    comp.structure.clamp(comp.clamp_nodes[0])
    asm = comp.structure.assemble()
    w2 = sla.eigh(asm.K.toarray(), asm.M.toarray(), eigvals_only=True)
    return np.sqrt(w2) / (2 * np.pi)


def test_clamped_free_tube_frequencies_analytic():
    sec = tube_section(DIAMETER, WALL)
    f = _clamped_frequencies(20)
    f_bend = _first_bending_hz(sec)
    f_tors = np.sqrt(STEEL.G * sec.J / (STEEL.rho * sec.Ip)) / (4 * LENGTH)
    assert f[0] == pytest.approx(f_bend, rel=5e-3)
    assert f[1] == pytest.approx(f_bend, rel=5e-3)
    torsion = f[np.argmin(np.abs(f - f_tors))]
    assert torsion == pytest.approx(f_tors, rel=5e-3)
    # Euler-Bernoulli would be 0.7 % higher: the test sees the shear and rotary terms
    f_euler = 1.875104**2 / (2 * np.pi * LENGTH**2) * np.sqrt(STEEL.E * sec.Iy
                                                             / (STEEL.rho * sec.A))
    assert abs(f[0] / f_euler - 1) > 2 * abs(f[0] / f_bend - 1)


def test_clamped_free_tube_frequencies_converge():
    sec = tube_section(DIAMETER, WALL)
    f_bend = _first_bending_hz(sec)
    counts = np.array([4, 8, 16, 32])
    errors = np.array([_clamped_frequencies(n)[0] / f_bend - 1 for n in counts])
    assert np.all(errors > 0) and np.all(np.diff(errors) < 0)
    rate = -np.polyfit(np.log(counts), np.log(errors), 1)[0]
    assert 1.8 < rate < 2.3   # consistent mass, linear-in-shear element: second order


def test_pitched_tube_same_frequencies_roundtrip():
    assert np.allclose(_clamped_frequencies(6, 35.0), _clamped_frequencies(6, 0.0), rtol=1e-9)


def _first_torsion_hz(count):
    """First clamped-free torsion frequency [Hz] of the tube mesh: the mode whose motion is
    mostly twist about the tube axis (x)."""
    comp = tube_component(LENGTH, DIAMETER, WALL, 0.0, STEEL, count)
    comp.structure.clamp(comp.clamp_nodes[0])
    asm = comp.structure.assemble()
    w2, modes = sla.eigh(asm.K.toarray(), asm.M.toarray())
    twist = np.zeros(asm.K.shape[0], bool)
    for node in range(1, count + 1):
        twist[asm.node_dofs(node)[3]] = True
    share = np.sum(modes[twist] ** 2, axis=0) / np.sum(modes**2, axis=0)
    return np.sqrt(w2[np.flatnonzero(share > 0.99)[0]]) / (2 * np.pi)


def test_clamped_free_tube_torsion_converges():
    """Twist is a linear element with consistent mass: its first clamped-free frequency is the
    rod's discrete dispersion omega^2 = (6 c^2 / h^2) (1 - cos k h) / (2 + cos k h), k = pi / 2L,
    c^2 = G J / (rho I_p), exactly at every mesh; it lies above the continuum's f = c / 4L and
    converges to it at second order with refinement."""
    sec = tube_section(DIAMETER, WALL)
    speed = np.sqrt(STEEL.G * sec.J / (STEEL.rho * sec.Ip))
    f_exact = speed / (4 * LENGTH)
    counts = np.array([2, 4, 8, 16, 32])
    freqs = np.array([_first_torsion_hz(n) for n in counts])
    for n, f in zip(counts, freqs):
        kh = np.pi / (2 * LENGTH) * LENGTH / n
        w2 = 6 * speed**2 / (LENGTH / n) ** 2 * (1 - np.cos(kh)) / (2 + np.cos(kh))
        assert f == pytest.approx(np.sqrt(w2) / (2 * np.pi), rel=1e-9), n
    errors = freqs / f_exact - 1
    assert np.all(errors > 0) and np.all(np.diff(errors) < 0)
    rate = -np.polyfit(np.log(counts), np.log(errors), 1)[0]
    assert 1.9 < rate < 2.1
    # leading term of the dispersion: f_h / f = 1 + (k h)^2 / 24 (1.0e-4 at 32 elements)
    assert errors[-1] == pytest.approx((np.pi / (2 * counts[-1])) ** 2 / 24, rel=0.01)
