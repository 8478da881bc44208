"""Craig-Bampton reduction against the full finite-element model (second formulation)."""
import numpy as np
import pytest
import scipy.linalg as sla
import scipy.sparse.linalg as spla
from deviations import known_deviation

from motoflex_ros.config import MOTORCYCLE_COMPONENTS
from motoflex_ros.formats.component_file import load_component
from motoflex_ros.structures.beam import Material
from motoflex_ros.structures.component_model import tube_component
from motoflex_ros.structures.craig_bampton import craig_bampton
from motoflex_ros.structures.full_model import full_clamped_matrices


def _full_clamped(component):
    """Full model with the clamps applied: (K, M, free-DOF indices of the loaded end)."""
    k, m, asm = full_clamped_matrices(component)
    return k, m, asm.node_dofs(component.loaded_end)


@pytest.mark.parametrize("name", MOTORCYCLE_COMPONENTS)
def test_static_loaded_end_equals_full_model_roundtrip(name):
    comp = load_component(name)
    red = comp.clamped_reduced()
    k, _, end = _full_clamped(comp)
    for wrench in np.eye(6) * np.array([500.0, 500.0, 500.0, 50.0, 50.0, 50.0]):
        f = np.zeros(k.shape[0])
        f[end] = wrench
        full = spla.spsolve(k.tocsc(), f)[end]
        reduced = red.static_end_motion(wrench)
        assert np.allclose(reduced, full, rtol=1e-9, atol=1e-9 * np.abs(full).max())


def _compare_frequencies(name, f_limit):
    comp = load_component(name)
    red = comp.clamped_reduced()
    k, m, _ = _full_clamped(comp)
    w2 = spla.eigsh(k, k=30, M=m, sigma=0.0, which="LM", return_eigenvectors=False)
    full = np.sort(np.sqrt(w2)) / (2 * np.pi)
    full = full[full < f_limit]
    assert len(full) >= 1
    return red.frequencies_hz[:len(full)], full


# Issue 3 asks for 0.5 % below 300 Hz with at most 20 fixed-interface modes, none above 600 Hz.
# Our beam models have only 2-11 fixed-interface modes below 600 Hz, and the clamped modes at
# 230-290 Hz come out 1-3 % high (truncation: (f / f_cut)^2 is already 0.15 there). Kept as a
# strict xfail so that it reports when a model or the reduction starts to meet it.
@known_deviation("cb-truncation", "CB truncation at 600 Hz: 1-3 % high at 230-290 Hz")
@pytest.mark.parametrize("name", MOTORCYCLE_COMPONENTS)
def test_eigenfrequencies_below_300hz_equal_full_model(name):
    reduced, full = _compare_frequencies(name, 300.0)
    assert np.allclose(reduced, full, rtol=5e-3)


@pytest.mark.parametrize("name", MOTORCYCLE_COMPONENTS)
def test_table1_modes_equal_full_model(name):
    """The first torsion and bending modes below 300 Hz (Table 1's, except the swingarm
    torsion at 321 Hz) agree with the nearest full-model mode within 0.5 %."""
    comp = load_component(name)
    red = comp.clamped_reduced()
    k, m, _ = _full_clamped(comp)
    w2 = spla.eigsh(k, k=30, M=m, sigma=0.0, which="LM", return_eigenvectors=False)
    full = np.sqrt(w2) / (2 * np.pi)
    checked = 0
    for label in ("torsion", "bending"):
        f = red.frequency(label)
        if f < 300.0:
            assert np.min(np.abs(full / f - 1)) < 5e-3, (label, f)
            checked += 1
    assert checked >= 1


def test_all_modes_kept_reproduces_full_eigenvalues():
    steel = Material(2.1e11, 8.1e10, 7850.0)
    comp = tube_component(0.6, 0.04, 0.002, 20.0, steel, 6)
    red = comp.clamped_reduced(n_modes=10_000, f_max_hz=1e9)
    k, m, _ = _full_clamped(comp)
    full = np.sqrt(sla.eigh(k.toarray(), m.toarray(), eigvals_only=True)) / (2 * np.pi)
    assert red.n == len(full)
    assert np.allclose(red.frequencies_hz, full, rtol=1e-9)


def test_mode_count_and_frequency_limit():
    comp = load_component("frame")
    cb, _ = comp.craig_bampton(n_modes=20, f_max_hz=600.0)
    assert cb.n_modes <= 20 and np.all(cb.frequencies_hz <= 600.0)
    few, _ = comp.craig_bampton(n_modes=3)
    assert few.n_modes == 3
    assert np.allclose(few.frequencies_hz, cb.frequencies_hz[:3], rtol=1e-8)


def test_modal_damping_ratio_roundtrip():
    red = load_component("front_assembly").clamped_reduced(zeta=0.02)
    a, _ = red.state_space()
    lam = np.linalg.eigvals(a)
    lam = lam[lam.imag > 0]
    zeta = -lam.real / np.abs(lam)
    assert np.allclose(zeta, 0.02, rtol=1e-6)
    assert np.allclose(np.sort(np.abs(lam)) / (2 * np.pi), red.frequencies_hz, rtol=1e-6)


def test_expand_to_all_nodes_matches_full_model():
    comp = load_component("swingarm")
    red = comp.clamped_reduced()
    wrench = np.array([0.0, 300.0, 0.0, 0.0, 0.0, 0.0])
    x = np.linalg.solve(red.K, red.end_load_vector(wrench))
    nodes = red.node_displacements(x)
    assert np.allclose(nodes[comp.loaded_end], red.static_end_motion(wrench), rtol=1e-12)
    assert np.allclose(nodes[list(comp.clamp_nodes)], 0.0)


def test_craig_bampton_static_exact_for_boundary_loads():
    """Generic reduction (no clamps): the constraint modes make boundary statics exact."""
    steel = Material(2.1e11, 8.1e10, 7850.0)
    comp = tube_component(0.5, 0.03, 0.002, 0.0, steel, 12)
    asm = comp.assembled()
    boundary = np.concatenate([asm.node_dofs(n) for n in comp.interface_nodes])
    cb = craig_bampton(asm.K, asm.M, boundary, n_modes=4)
    clamp = np.arange(6)
    keep = np.arange(6, cb.K.shape[0])
    f = np.zeros(len(keep))
    f[1] = 100.0
    reduced = np.linalg.solve(cb.K[np.ix_(keep, keep)], f)[:6]
    free = np.setdiff1d(np.arange(asm.K.shape[0]), boundary[clamp])
    k = asm.K[free][:, free].toarray()
    f_full = np.zeros(len(free))
    tip = np.searchsorted(free, boundary[6:])
    f_full[tip[1]] = 100.0
    assert np.allclose(reduced, np.linalg.solve(k, f_full)[tip], rtol=1e-9)
