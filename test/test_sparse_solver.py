"""The sparse factorisation behind Craig-Bampton (issue 15): MKL PARDISO's Cholesky against
scipy's SuperLU (a second, independent factorisation) on a small solid mesh, and the fallback
to SuperLU when pypardiso cannot be imported.

Degenerate modes (the square box's bending pairs) are compared as subspaces, frequencies
sorted: no test depends on the order ARPACK returns a degenerate pair in.
"""
import sys

import numpy as np
import pytest
import scipy.sparse as sp

from motoflex_ros.errors import ModelError
from motoflex_ros.formats.mesh_examples import box_mesh
from motoflex_ros.structures import sparse_solver
from motoflex_ros.structures.craig_bampton import craig_bampton, interior_blocks
from motoflex_ros.structures.solid import SolidBlock, assemble_solid
from motoflex_ros.structures.sparse_solver import factorize_spd, pardiso_available

needs_pardiso = pytest.mark.skipif(not pardiso_available(), reason="pypardiso not installed")


@pytest.fixture(scope="module")
def box():
    """A steel box cantilever 0.6 x 0.05 x 0.05 m of quadratic tetrahedra (about 5,000 DOFs):
    (K [N/m], M [kg], boundary DOFs = all DOFs of the end faces x = 0 and x = L)."""
    points, cells = box_mesh(0.6, 0.05, 0.05, (24, 2, 2), "tetra10")
    k, m = assemble_solid(points, [SolidBlock("tetra10", cells, np.arange(len(cells)))],
                          2.1e11, 0.3, 7850.0)
    x = points[:, 0]
    ends = np.flatnonzero(np.isclose(x, 0.0) | np.isclose(x, x.max()))
    return k, m, (3 * ends[:, None] + np.arange(3)).ravel()


def _reduce(box, solver):
    k, m, boundary = box
    return craig_bampton(k, m, boundary, n_modes=20, f_max_hz=1e6, solver=solver)


def _same_subspace(a, b, m):
    """Largest residual of the M-orthogonal projection of the columns of a onto span(b)
    (b M-orthonormal), relative to a's largest entry."""
    return np.abs(a - b @ (b.T @ (m @ a))).max() / np.abs(a).max()


@needs_pardiso
def test_pardiso_equals_superlu(box):
    """Constraint modes and fixed-interface frequencies equal to 1e-9 relative; the modes span
    the same subspace; the reduced models have the same eigenvalues."""
    k, m, boundary = box
    pardiso, superlu = _reduce(box, "pardiso"), _reduce(box, "superlu")
    nb = len(boundary)
    psi_p, psi_s = pardiso.transform[:, :nb], superlu.transform[:, :nb]
    assert np.abs(psi_p - psi_s).max() <= 1e-9 * np.abs(psi_s).max()
    assert pardiso.n_modes == superlu.n_modes == 20
    assert np.allclose(np.sort(pardiso.frequencies_hz), np.sort(superlu.frequencies_hz),
                       rtol=1e-9, atol=0)
    interior, _, m_ii, _ = interior_blocks(k, m, boundary)
    phi_p, phi_s = pardiso.transform[interior, nb:], superlu.transform[interior, nb:]
    assert _same_subspace(phi_p, phi_s, m_ii) < 1e-7
    lam_p = np.sort(np.linalg.eigvals(np.linalg.solve(pardiso.M, pardiso.K)).real)
    lam_s = np.sort(np.linalg.eigvals(np.linalg.solve(superlu.M, superlu.K)).real)
    assert np.allclose(lam_p, lam_s, rtol=1e-9, atol=1e-9 * lam_s.max())


@needs_pardiso
def test_pardiso_solves_many_right_hand_sides(box):
    """One factorisation: k right-hand sides in one call equal k single solves, the residual is
    round-off, and the answer does not depend on MKL's thread count beyond round-off."""
    k, m, boundary = box
    _, k_ii, _, k_ib = interior_blocks(k, m, boundary)
    with factorize_spd(k_ii, "pardiso", threads=1) as one, \
            factorize_spd(k_ii, "pardiso", threads=2) as two:
        assert one.solver == "pardiso" and one.factor_entries > k_ii.nnz // 2
        block = one.solve(k_ib)
        columns = np.column_stack([one.solve(k_ib[:, j]) for j in range(k_ib.shape[1])])
        assert np.abs(block - columns).max() <= 1e-12 * np.abs(block).max()
        assert np.abs(k_ii @ block - k_ib).max() <= 1e-8 * np.abs(k_ib).max()
        assert np.abs(two.solve(k_ib) - block).max() <= 1e-10 * np.abs(block).max()
        assert np.allclose(one.operator() @ k_ib[:, 0], block[:, 0], rtol=0,
                           atol=1e-12 * np.abs(block).max())


@needs_pardiso
def test_pardiso_singular_stiffness_is_one_clear_error(box):
    """The free box (six rigid-body modes) cannot be factorised: ModelError, not garbage."""
    k, _, _ = box
    with pytest.raises(ModelError, match="interior stiffness is singular"):
        factorize_spd(k, "pardiso")
    with pytest.raises(ModelError, match="interior stiffness is singular"):
        factorize_spd(sp.diags([1.0, 0.0, 2.0]).tocsr(), "pardiso")


def test_auto_takes_superlu_below_the_size_and_pardiso_from_it(box, monkeypatch):
    """'auto' factorises a matrix below PARDISO_MIN_SIZE rows (the shipped components, a few
    hundred DOFs; this 5k-DOF box) with SuperLU, whose result does not depend on memory
    alignment, and one of at least that size with PARDISO when it is installed."""
    _, k_ii, _, _ = interior_blocks(*box)
    assert k_ii.shape[0] < sparse_solver.PARDISO_MIN_SIZE
    assert factorize_spd(k_ii).solver == "superlu"
    monkeypatch.setattr(sparse_solver, "PARDISO_MIN_SIZE", k_ii.shape[0])
    assert factorize_spd(k_ii).solver == ("pardiso" if pardiso_available() else "superlu")


def test_fallback_without_pypardiso(box, monkeypatch):
    """With pypardiso unimportable, 'auto' takes SuperLU and gives the same reduction (to
    1e-9) as with it; asking for 'pardiso' explicitly is one clear error."""
    _, k_ii, _, _ = interior_blocks(*box)
    monkeypatch.setattr(sparse_solver, "PARDISO_MIN_SIZE", k_ii.shape[0])   # 'auto': PARDISO
    with_it = _reduce(box, "auto")
    monkeypatch.setitem(sys.modules, "pypardiso", None)   # import pypardiso -> ImportError
    assert not pardiso_available()
    _, k_ii, _, _ = interior_blocks(*box)
    assert factorize_spd(k_ii).solver == "superlu"
    with pytest.raises(ModelError, match="needs the pypardiso package"):
        factorize_spd(k_ii, "pardiso")
    without = _reduce(box, "auto")
    nb = len(box[2])
    assert np.abs(with_it.transform[:, :nb] - without.transform[:, :nb]).max() <= \
        1e-9 * np.abs(without.transform[:, :nb]).max()
    assert np.allclose(np.sort(with_it.frequencies_hz), np.sort(without.frequencies_hz),
                       rtol=1e-9, atol=0)
