"""Eigenpair continuation over speed: track a few modes without full decompositions.

For each run r, tracked mode k and speed index j, the eigenpair (lambda, x) of the state
matrix A_r(v_j) [1/s] is found by Newton's method on the bordered system

    (A - lambda I) x = 0,     c^H x = 1,

    [A - lambda I   -x] [dx      ]     [(A - lambda I) x]
    [c^H             0] [dlambda ] = - [c^H x - 1       ],

with c the previous speed's (unit) eigenvector, which fixes scale and phase and keeps the
iteration on the same branch. The start of each step is a polynomial extrapolation (up to
quadratic, in speed) of the last three eigenpairs, so that one Newton step usually meets the
tolerance. All runs and modes of one speed are solved in one batched call (np.linalg.solve);
each (run, mode) stops iterating on its own residual, so a run's result does not depend on
which other runs share its batch.

The converged eigenvector is rescaled to unit 2-norm (a real factor: the phase stays
continuous). ``step_mac`` is the modal assurance criterion between consecutive eigenvectors;
a value far below 1 means the speed step was too coarse for that mode (refine the grid).
"""
from dataclasses import dataclass

import numpy as np

from motoflex_ros.errors import ModelError

__all__ = ["ContinuationResult", "continue_eigenpairs", "nearest_eigenpairs", "mac"]


@dataclass(frozen=True, eq=False)
class ContinuationResult:
    """Tracked eigenpairs over speed.

    eigenvalues: (runs, speeds, modes) complex [1/s]; eigenvectors: (runs, speeds, n, modes)
    complex unit vectors, or None if not kept; iterations: Newton steps per point (0: the
    predictor already met the tolerance); residual: ||A x - lambda x|| / (||A||_F ||x||);
    step_mac: MAC between the eigenvectors of consecutive speeds (1 at the first speed);
    tol: the residual tolerance used.
    """

    eigenvalues: np.ndarray
    eigenvectors: np.ndarray
    iterations: np.ndarray
    residual: np.ndarray
    step_mac: np.ndarray
    tol: float

    @property
    def converged(self):
        """True where the relative residual met the tolerance."""
        return self.residual <= self.tol


def mac(x, y):
    """Modal assurance criterion |x^H y|^2 / (|x|^2 |y|^2) over axis -2 (vectors in columns)."""
    num = np.abs(np.sum(np.conj(x) * y, axis=-2)) ** 2
    return num / (np.sum(np.abs(x) ** 2, axis=-2) * np.sum(np.abs(y) ** 2, axis=-2))


def nearest_eigenpairs(matrices, targets):
    """Eigenpairs of each matrix nearest to target eigenvalues (a full decomposition).

    Parameters
    ----------
    matrices : array (runs, n, n)
        State matrices at the starting speed [1/s].
    targets : array (modes,) or (runs, modes), complex
        Approximate eigenvalues to pick (e.g. weave near -1 + 2 pi 2.5 i) [1/s].

    Returns
    -------
    (eigenvalues (runs, modes), eigenvectors (runs, n, modes) unit 2-norm)

    """
    values, vectors = np.linalg.eig(np.asarray(matrices))
    targets = np.asarray(targets, dtype=complex)
    if targets.ndim == 1:
        targets = np.broadcast_to(targets, (values.shape[0], targets.size))
    pick = np.argmin(np.abs(values[:, :, None] - targets[:, None, :]), axis=1)
    if any(np.unique(row).size < row.size for row in pick):
        raise ModelError("two target eigenvalues select the same eigenvalue")
    lam = np.take_along_axis(values, pick, axis=1)
    vec = np.take_along_axis(vectors, pick[:, None, :], axis=2)
    return lam.astype(complex), vec.astype(complex) / np.linalg.norm(vec, axis=1, keepdims=True)


def _matrix_source(matrices, n_speeds):
    """A function j -> (runs, n, n) and the number of speeds."""
    if callable(matrices):
        if n_speeds is None:
            raise ModelError("a callable of state matrices needs the speeds (or n_speeds)")
        return (lambda j: np.asarray(matrices(j))), int(n_speeds)
    array = np.asarray(matrices)
    if array.ndim == 3:
        array = array[None]
    if array.ndim != 4 or array.shape[-1] != array.shape[-2]:
        raise ModelError(f"state matrices must be (runs, speeds, n, n), got {array.shape}")
    return (lambda j: array[:, j]), array.shape[1]


def _extrapolate(history, speed):
    """Lagrange extrapolation of the stored (speed, lambda, x) points to ``speed``."""
    speeds = [h[0] for h in history]
    lam = np.zeros_like(history[-1][1])
    vec = np.zeros_like(history[-1][2])
    for i, (v_i, lam_i, x_i) in enumerate(history):
        weight = np.prod([(speed - v_m) / (v_i - v_m) for m, v_m in enumerate(speeds) if m != i])
        lam = lam + weight * lam_i
        vec = vec + weight * x_i
    return lam, vec


def _residual(a, lam, x, a_norm):
    """Relative residual ||A x - lambda x|| / (||A||_F ||x||), per (batch)."""
    r = np.einsum("bij,bj->bi", a, x) - lam[:, None] * x
    return np.linalg.norm(r, axis=1) / (a_norm * np.linalg.norm(x, axis=1))


def _newton_step(a, lam, x, c):
    """One bordered Newton step for a batch: a (b, n, n), lam (b,), x (b, n), c (b, n)."""
    b, n = x.shape
    eye = np.eye(n)
    jac = np.zeros((b, n + 1, n + 1), dtype=complex)
    jac[:, :n, :n] = a - lam[:, None, None] * eye
    jac[:, :n, n] = -x
    jac[:, n, :n] = np.conj(c)
    rhs = np.empty((b, n + 1), dtype=complex)
    rhs[:, :n] = -np.einsum("bij,bj->bi", jac[:, :n, :n], x)
    rhs[:, n] = 1.0 - np.sum(np.conj(c) * x, axis=1)
    step = np.linalg.solve(jac, rhs[..., None])[..., 0]
    return lam + step[:, n], x + step[:, :n]


def _correct(a, lam, x, c, tol, max_iter):
    """Newton iterations on the batch until each member's residual <= tol."""
    a_norm = np.linalg.norm(a, axis=(1, 2))
    res = _residual(a, lam, x, a_norm)
    iters = np.zeros(lam.shape, dtype=int)
    for _ in range(max_iter):
        active = np.flatnonzero(res > tol)
        if active.size == 0:
            break
        lam[active], x[active] = _newton_step(a[active], lam[active], x[active], c[active])
        res[active] = _residual(a[active], lam[active], x[active], a_norm[active])
        iters[active] += 1
    return lam, x, iters, res


def _flat(array_rk):
    """(runs, n, modes) -> (runs * modes, n); (runs, modes) -> (runs * modes,)."""
    if array_rk.ndim == 3:
        return np.moveaxis(array_rk, 2, 1).reshape(-1, array_rk.shape[1])
    return array_rk.reshape(-1)


def continue_eigenpairs(matrices, eigenvalues0, eigenvectors0, speeds=None, n_speeds=None,
                        tol=1e-12, max_iter=8, keep_vectors=False):
    """Continue eigenpairs of A(v) over a speed grid from those at the first speed.

    Parameters
    ----------
    matrices : array (runs, speeds, n, n) or (speeds, n, n), or callable
        State matrices [1/s]; a callable ``matrices(j) -> (runs, n, n)`` gives those of speed
        index j (nothing is stored for all speeds at once).
    eigenvalues0 : array (runs, modes) complex
        Eigenvalues at the first speed [1/s] (e.g. from :func:`nearest_eigenpairs`).
    eigenvectors0 : array (runs, n, modes) complex
        Matching eigenvectors (any scale).
    speeds : array (speeds,), optional
        Speeds [m/s] (used by the predictor); default equally spaced.
    n_speeds : int, optional
        Number of speeds when ``matrices`` is callable and ``speeds`` is not given.
    tol : float
        Relative residual tolerance ||A x - lambda x|| / (||A||_F ||x||).
    max_iter : int
        Newton steps allowed per speed.
    keep_vectors : bool
        Store the eigenvectors at every speed.

    """
    n_speeds = len(speeds) if speeds is not None else n_speeds
    get, n_speeds = _matrix_source(matrices, n_speeds)
    grid = np.arange(n_speeds, dtype=float) if speeds is None else np.asarray(speeds, float)
    lam0 = np.atleast_2d(np.asarray(eigenvalues0, dtype=complex))
    vec0 = np.asarray(eigenvectors0, dtype=complex).reshape(lam0.shape[0], -1, lam0.shape[1])
    runs, n, modes = vec0.shape
    lam, x = _flat(lam0).copy(), _flat(vec0).copy()
    x /= np.linalg.norm(x, axis=1, keepdims=True)
    lam, x, iters, res = _correct(np.repeat(get(0), modes, axis=0), lam, x, x.copy(),
                                  tol, max_iter)
    out = _Recorder(runs, n_speeds, n, modes, keep_vectors)
    out.store(0, lam, x, iters, res, np.ones_like(res))
    history = [(grid[0], lam.copy(), x.copy())]
    for j in range(1, n_speeds):
        a = np.repeat(get(j), modes, axis=0)
        lam_p, x_p = _extrapolate(history, grid[j])
        c = history[-1][2]
        x_p = x_p / np.sum(np.conj(c) * x_p, axis=1, keepdims=True)
        lam, x, iters, res = _correct(a, lam_p, x_p, c, tol, max_iter)
        x /= np.linalg.norm(x, axis=1, keepdims=True)
        out.store(j, lam, x, iters, res, mac(c[..., None], x[..., None])[:, 0])
        history = (history + [(grid[j], lam.copy(), x.copy())])[-3:]
    return out.result(tol)


class _Recorder:
    """Collects per-speed results of the flattened (runs * modes) batch."""

    def __init__(self, runs, n_speeds, n, modes, keep_vectors):
        self.shape = (runs, modes)
        self.lam = np.empty((runs, n_speeds, modes), dtype=complex)
        self.iters = np.empty((runs, n_speeds, modes), dtype=int)
        self.res = np.empty((runs, n_speeds, modes))
        self.mac = np.empty((runs, n_speeds, modes))
        self.vec = np.empty((runs, n_speeds, n, modes), dtype=complex) if keep_vectors else None

    def store(self, j, lam, x, iters, res, step_mac):
        runs, modes = self.shape
        self.lam[:, j] = lam.reshape(runs, modes)
        self.iters[:, j] = iters.reshape(runs, modes)
        self.res[:, j] = res.reshape(runs, modes)
        self.mac[:, j] = step_mac.reshape(runs, modes)
        if self.vec is not None:
            self.vec[:, j] = np.moveaxis(x.reshape(runs, modes, -1), 1, 2)

    def result(self, tol):
        return ContinuationResult(eigenvalues=self.lam, eigenvectors=self.vec,
                                  iterations=self.iters, residual=self.res, step_mac=self.mac,
                                  tol=tol)
