"""Eigenpair continuation against numpy.linalg.eig and the published Whipple eigenvalues."""
import numpy as np
import pytest

from motoflex_ros.errors import ModelError
from motoflex_ros.study.continuation import continue_eigenpairs, mac, nearest_eigenpairs
from motoflex_ros.study.stability_index import crossing_speeds

# Whipple bicycle benchmark ([Meijaard 2007], docs/references.md#meijaard-2007), g = 9.81 m/s^2
M = np.array([[80.81722, 2.31941332208709], [2.31941332208709, 0.29784188199686]])
C1 = np.array([[0.0, 33.86641391492494], [-0.85035641456978, 1.68540397397560]])
K0 = np.array([[-80.95, -2.59951685249872], [-2.59951685249872, -0.80329488458618]])
K2 = np.array([[0.0, 76.59734589573222], [0.0, 2.65431523794604]])


def whipple_state_matrix(v):
    m_inv = np.linalg.inv(M)
    return np.block([[np.zeros((2, 2)), np.eye(2)],
                     [-m_inv @ (9.81 * K0 + v**2 * K2), -m_inv @ (v * C1)]])


def eig_reference_tracking(matrices, start):
    """Reference: full eig at every speed, following the nearest eigenvalue (fine grid)."""
    current = np.array(start, dtype=complex)
    out = []
    for a in matrices:
        values = np.linalg.eigvals(a)
        current = values[np.argmin(np.abs(values[:, None] - current[None, :]), axis=0)]
        out.append(current)
    return np.array(out)


def test_whipple_published():
    speeds = np.linspace(3.0, 10.0, 141)
    a = np.array([whipple_state_matrix(v) for v in speeds])
    lam0, vec0 = nearest_eigenpairs(a[None, 0], [1.7 + 2.3j, -2.6])  # weave, capsize
    result = continue_eigenpairs(a, lam0, vec0, speeds=speeds)
    lam = result.eigenvalues[0]
    i5, i10 = np.searchsorted(speeds, [5.0, 10.0])
    np.testing.assert_allclose(lam[i5], [-0.77534188219585 + 4.46486771378823j,
                                         -0.32286642900409], atol=1e-11)
    np.testing.assert_allclose(lam[i10], [-3.72016840437287 + 10.90681139476287j,
                                          0.16105338653172], atol=1e-11)
    assert np.all(result.converged) and result.step_mac.min() > 0.99


def test_whipple_weave_speed_against_root_finding():
    from scipy.optimize import brentq

    def weave_real(v):
        values = np.linalg.eigvals(whipple_state_matrix(v))
        return values[np.argmax(values.imag)].real

    v_weave = brentq(weave_real, 4.0, 4.6, xtol=1e-14)
    assert v_weave == pytest.approx(4.292382, abs=1e-6)  # Meijaard et al. 2007
    speeds = np.linspace(3.0, 6.0, 301)
    a = np.array([whipple_state_matrix(v) for v in speeds])
    lam0, vec0 = nearest_eigenpairs(a[None, 0], [1.7 + 2.3j])
    weave = continue_eigenpairs(a, lam0, vec0, speeds=speeds).eigenvalues[0, :, 0]
    crossing = crossing_speeds(speeds, weave.real)
    assert crossing.size == 1 and crossing[0] == pytest.approx(v_weave, abs=1e-4)


def random_family(n, runs, seed):
    rng = np.random.default_rng(seed)
    a0 = rng.standard_normal((runs, n, n))
    a1 = rng.standard_normal((runs, n, n))
    return lambda v: a0 + v * a1


def test_random_matrices_match_eig():
    family = random_family(12, 4, seed=11)
    speeds = np.linspace(0.0, 0.2, 41)  # run 3's second mode nears a collision after 0.2
    a = np.stack([family(v) for v in speeds], axis=1)  # (runs, speeds, n, n)
    values0 = np.linalg.eigvals(a[:, 0])
    # two oscillatory modes per run, those with the largest imaginary parts; modes near the
    # real axis can meet their conjugate and turn real (see the collision test below)
    targets = np.sort_complex(values0 * 1j)[:, :2] / 1j
    assert np.all(targets.imag > 1.0)
    lam0, vec0 = nearest_eigenpairs(a[:, 0], targets)
    result = continue_eigenpairs(a, lam0, vec0, speeds=speeds, keep_vectors=True)
    assert np.all(result.converged)
    for r in range(4):
        reference = eig_reference_tracking(a[r], lam0[r])
        scale = np.abs(reference).max()
        np.testing.assert_allclose(result.eigenvalues[r], reference, rtol=0,
                                   atol=1e-10 * scale)
    # eigenvectors are unit eigenvectors of the matrices
    x = result.eigenvectors
    ax = np.einsum("rsij,rsjm->rsim", a, x)
    np.testing.assert_allclose(ax, x * result.eigenvalues[:, :, None, :], atol=1e-10)
    np.testing.assert_allclose(np.linalg.norm(x, axis=2), 1.0, atol=1e-14)


def random_sweep(n, runs, seed, speeds):
    """Matrices (runs, speeds, n, n) of a random family and start pairs of two modes."""
    family = random_family(n, runs, seed)
    a = np.stack([family(v) for v in speeds], axis=1)
    lam0, vec0 = nearest_eigenpairs(a[:, 0], np.linalg.eigvals(a[:, 0])[:, :2])
    return family, a, lam0, vec0


def test_converged_points_are_eigenvalues_even_near_collisions():
    # over the longer range some tracked modes approach defective points; wherever the
    # result says converged, the value must be an eigenvalue of that matrix
    family = random_family(12, 4, seed=11)
    speeds = np.linspace(0.0, 0.3, 61)
    a = np.stack([family(v) for v in speeds], axis=1)
    values0 = np.linalg.eigvals(a[:, 0])
    lam0, vec0 = nearest_eigenpairs(a[:, 0], np.sort_complex(values0 * 1j)[:, :2] / 1j)
    result = continue_eigenpairs(a, lam0, vec0, speeds=speeds)
    assert result.converged.mean() > 0.9
    for r, j, m in np.argwhere(result.converged):
        values = np.linalg.eigvals(a[r, j])
        assert np.min(np.abs(values - result.eigenvalues[r, j, m])) < 1e-9 * np.abs(values).max()


def test_callable_source_equals_array_source():
    speeds = np.linspace(0.0, 0.2, 21)
    family, a, lam0, vec0 = random_sweep(8, 3, 5, speeds)
    from_array = continue_eigenpairs(a, lam0, vec0, speeds=speeds)
    from_callable = continue_eigenpairs(lambda j: family(speeds[j]), lam0, vec0, speeds=speeds)
    np.testing.assert_array_equal(from_array.eigenvalues, from_callable.eigenvalues)


def test_batch_composition_does_not_change_results():
    speeds = np.linspace(0.0, 0.2, 21)
    _, a, lam0, vec0 = random_sweep(10, 6, 9, speeds)
    together = continue_eigenpairs(a, lam0, vec0, speeds=speeds)
    alone = continue_eigenpairs(a[2:3], lam0[2:3], vec0[2:3], speeds=speeds)
    np.testing.assert_array_equal(together.eigenvalues[2:3], alone.eigenvalues)


def close_pair_family(gap, seed=3):
    """Two complex modes whose frequencies cross while their real parts differ by ``gap``.

    A(v) = Q blockdiag(B1(v), B2(v), B3) Q^-1 with B(v) = [[sigma, w], [-w, sigma]]; the
    mode shapes are fixed, so the right continuation keeps each block's eigenvalue, whereas
    sorting by frequency would swap them at the crossing (v = 0.5).
    """
    rng = np.random.default_rng(seed)
    q = np.linalg.qr(rng.standard_normal((6, 6)))[0] + 0.3 * rng.standard_normal((6, 6))

    def block(sigma, w):
        return np.array([[sigma, w], [-w, sigma]])

    def a(v):
        blocks = [block(-1.0, 5.0 + 2.0 * v), block(-1.0 - gap, 6.0 - 0.0 * v),
                  block(-3.0, 20.0)]
        d = np.zeros((6, 6))
        for i, b in enumerate(blocks):
            d[2 * i:2 * i + 2, 2 * i:2 * i + 2] = b
        return q @ d @ np.linalg.inv(q)

    return a


@pytest.mark.parametrize("gap", [1e-2, 1e-4])
def test_close_eigenvalues_keep_their_mode(gap):
    family = close_pair_family(gap)
    speeds = np.linspace(0.0, 1.0, 101)  # frequency of mode 1 passes 6 at v = 0.5
    a = np.stack([family(v) for v in speeds])[None]
    lam0, vec0 = nearest_eigenpairs(a[:, 0], [-1.0 + 5.0j, -1.0 - gap + 6.0j])
    result = continue_eigenpairs(a, lam0, vec0, speeds=speeds)
    lam = result.eigenvalues[0]
    np.testing.assert_allclose(lam[:, 0], -1.0 + 1j * (5.0 + 2.0 * speeds), atol=1e-10)
    np.testing.assert_allclose(lam[:, 1], -1.0 - gap + 6.0j, atol=1e-10)
    # at the crossing the two tracked eigenvalues are only `gap` apart, yet distinct
    assert np.min(np.abs(lam[:, 0] - lam[:, 1])) == pytest.approx(gap, rel=1e-6)
    # the eigenvalues agree with numpy's at every speed
    for j in (0, 50, 100):
        values = np.linalg.eigvals(a[0, j])
        assert np.min(np.abs(values - lam[j, 0])) < 1e-10


def test_collision_of_real_eigenvalues_is_flagged():
    # the Whipple capsize-like and weave-precursor real eigenvalues meet near v = 0.684 m/s
    # and leave the real axis as the weave pair: a defective point that real eigenpairs
    # cannot be continued through; the result must say so instead of returning wrong values
    speeds = np.linspace(0.3, 1.0, 71)
    a = np.array([whipple_state_matrix(v) for v in speeds])
    real0 = np.sort(np.linalg.eigvals(a[0]).real)
    lam0, vec0 = nearest_eigenpairs(a[None, 0], real0[2:])  # the two largest real ones
    result = continue_eigenpairs(a, lam0, vec0, speeds=speeds)
    bad = ~result.converged | (result.step_mac < 0.5)
    assert not bad[0, :30].any()  # fine before the collision
    assert bad[0].any()


def test_mac_analytic():
    x = np.array([[1.0], [0.0]])
    y = np.array([[1.0], [1.0j]])
    assert mac(x, y)[0] == pytest.approx(0.5)
    assert mac(y, 3j * y)[0] == pytest.approx(1.0)


def test_same_target_twice_is_an_error():
    a = np.diag([1.0, 2.0, 3.0])[None]
    with pytest.raises(ModelError, match="same eigenvalue"):
        nearest_eigenpairs(a, [1.1, 0.9])


def test_callable_without_speeds_is_an_error():
    with pytest.raises(ModelError, match="speeds"):
        continue_eigenpairs(lambda j: np.eye(2)[None], [[1.0]], np.ones((1, 2, 1)))


def descriptor_family(seed=21, ny=8, nz=3):
    """E x' = A x with algebraic states: y' = A(v) y + B z, 0 = C y - z, mixed by P and Q.

    E is singular (rank ny); the finite eigenvalues are those of A(v) + B C.
    """
    rng = np.random.default_rng(seed)
    a0, a1 = rng.standard_normal((2, ny, ny))
    b, c = rng.standard_normal((ny, nz)), rng.standard_normal((nz, ny))
    p, q = rng.standard_normal((2, ny + nz, ny + nz))
    e = np.zeros((ny + nz, ny + nz))
    e[:ny, :ny] = np.eye(ny)

    def pencil(v):
        a = np.block([[a0 + v * a1, b], [c, -np.eye(nz)]])
        return p @ e @ q, p @ a @ q

    return pencil, (lambda v: a0 + v * a1 + b @ c)


def test_descriptor_pencil_matches_reduced_eig():
    pencil, reduced = descriptor_family()
    speeds = np.linspace(0.0, 0.25, 51)
    e, a = (np.stack(m)[None] for m in zip(*[pencil(v) for v in speeds]))
    assert np.linalg.matrix_rank(e[0, 0]) == 8
    values0 = np.linalg.eigvals(reduced(0.0))
    targets = np.sort_complex(values0 * 1j)[:2] / 1j  # the two highest frequencies
    lam0, vec0 = nearest_eigenpairs(a[:, 0], targets, descriptor=e[:, 0])
    np.testing.assert_allclose(lam0[0], targets, atol=1e-10)
    result = continue_eigenpairs((e, a), lam0, vec0, speeds=speeds)
    assert np.all(result.converged)
    reference = eig_reference_tracking([reduced(v) for v in speeds], lam0[0])
    np.testing.assert_allclose(result.eigenvalues[0], reference, atol=1e-9)
    pencils = continue_eigenpairs(lambda j: tuple(m[None] for m in pencil(speeds[j])),
                                  lam0, vec0, speeds=speeds)
    np.testing.assert_allclose(pencils.eigenvalues, result.eigenvalues, atol=1e-12)
