"""Eigenpair continuation over speed: track a few modes without full decompositions.

For each run r, tracked mode k and speed index j, the eigenpair (lambda, x) of the state
matrix A_r(v_j) [1/s] (or of the descriptor pencil E x' = A x, where E may be singular, as
with massless bodies) is found by Newton's method on the bordered system

    (A - lambda E) x = 0,     c^H x = 1,

    [A - lambda E   -E x] [dx      ]     [(A - lambda E) x]
    [c^H             0  ] [dlambda ] = - [c^H x - 1       ],

with c the previous speed's (unit) eigenvector, which fixes scale and phase and keeps the
iteration on the same branch. The start of each step is a polynomial extrapolation (up to
quartic, in speed) of the last five eigenpairs, so that one Newton step usually meets the
tolerance; a member that does not converge from there starts again from the previous
eigenpair. All runs and modes of one speed are solved in one batched call (np.linalg.solve);
each (run, mode) stops iterating on its own residual, so a run's result does not depend on
which other runs share its batch.

The converged eigenvector is rescaled to unit 2-norm (a real factor: the phase stays
continuous). Infinite eigenvalues of a singular E are never approached: each tracked pair
stays on its finite branch. ``step_mac`` is the modal assurance criterion between consecutive
eigenvectors; a value far below 1 means the speed step was too coarse for that mode (refine
the grid). A real eigenvalue that meets another one and turns complex (or a complex pair that
meets on the real axis) is a defective point that cannot be continued through: it shows as a
residual above the tolerance or a low step MAC.
"""
import math
from dataclasses import dataclass

import numpy as np
import scipy.linalg

from motoflex_ros.errors import ModelError

__all__ = ["ContinuationResult", "continue_eigenpairs", "nearest_eigenpairs", "mac"]

_HISTORY = 5
"""Eigenpairs kept for the predictor: a quartic extrapolation in speed."""


@dataclass(frozen=True, eq=False)
class ContinuationResult:
    """Tracked eigenpairs over speed.

    eigenvalues: (runs, speeds, modes) complex [1/s]; eigenvectors: (runs, speeds, n, modes)
    complex unit vectors, or None if not kept; iterations: Newton steps per point (0: the
    predictor already met the tolerance); residual: componentwise backward error (see
    :func:`continue_eigenpairs`);
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
        """True where the backward error met the tolerance."""
        return self.residual <= self.tol


def mac(x, y):
    """Modal assurance criterion |x^H y|^2 / (|x|^2 |y|^2) over axis -2 (vectors in columns)."""
    num = np.abs(np.sum(np.conj(x) * y, axis=-2)) ** 2
    return num / (np.sum(np.abs(x) ** 2, axis=-2) * np.sum(np.abs(y) ** 2, axis=-2))


def _all_eigenpairs(matrices, descriptor):
    """Eigenvalues (runs, n) and eigenvectors (runs, n, n); infinite ones set to nan."""
    if descriptor is None:
        return np.linalg.eig(np.asarray(matrices))
    pairs = [scipy.linalg.eig(a, e) for a, e in zip(np.asarray(matrices),
                                                     np.asarray(descriptor))]
    values = np.array([np.where(np.isfinite(v), v, np.nan) for v, _ in pairs])
    return values, np.array([vec for _, vec in pairs])


def nearest_eigenpairs(matrices, targets, descriptor=None):
    """Eigenpairs of each matrix nearest to target eigenvalues (a full decomposition).

    Parameters
    ----------
    matrices : array (runs, n, n)
        State matrices A at the starting speed [1/s].
    targets : array (modes,) or (runs, modes), complex
        Approximate eigenvalues to pick (e.g. weave near -1 + 2 pi 2.5 i) [1/s].
    descriptor : array (runs, n, n), optional
        E of the pencil E x' = A x (may be singular); default the identity.

    Returns
    -------
    (eigenvalues (runs, modes), eigenvectors (runs, n, modes) unit 2-norm)

    """
    values, vectors = _all_eigenpairs(matrices, descriptor)
    targets = np.asarray(targets, dtype=complex)
    if targets.ndim == 1:
        targets = np.broadcast_to(targets, (values.shape[0], targets.size))
    distance = np.abs(values[:, :, None] - targets[:, None, :])
    pick = np.argmin(np.where(np.isnan(distance), np.inf, distance), axis=1)
    if any(np.unique(row).size < row.size for row in pick):
        raise ModelError("two target eigenvalues select the same eigenvalue")
    lam = np.take_along_axis(values, pick, axis=1)
    vec = np.take_along_axis(vectors, pick[:, None, :], axis=2)
    return lam.astype(complex), vec.astype(complex) / np.linalg.norm(vec, axis=1, keepdims=True)


def _as_batch(array):
    array = np.asarray(array)
    array = array[None] if array.ndim == 3 else array
    if array.ndim != 4 or array.shape[-1] != array.shape[-2]:
        raise ModelError(f"state matrices must be (runs, speeds, n, n), got {array.shape}")
    return array


def _matrix_source(matrices, n_speeds):
    """A function j -> (E or None, A), each (runs, n, n), and the number of speeds."""
    if callable(matrices):
        if n_speeds is None:
            raise ModelError("a callable of state matrices needs the speeds (or n_speeds)")

        def get(j):
            out = matrices(j)
            return (None, np.asarray(out)) if not isinstance(out, tuple) else (
                np.asarray(out[0]), np.asarray(out[1]))

        return get, int(n_speeds)
    if isinstance(matrices, tuple):
        e, a = _as_batch(matrices[0]), _as_batch(matrices[1])
        return (lambda j: (e[:, j], a[:, j])), a.shape[1]
    a = _as_batch(matrices)
    return (lambda j: (None, a[:, j])), a.shape[1]


def _extrapolate(history, speed):
    """Lagrange extrapolation of the stored (speed, lambda, x) points to ``speed``."""
    speeds = [h[0] for h in history]
    lam = np.zeros_like(history[-1][1])
    vec = np.zeros_like(history[-1][2])
    for i, (v_i, lam_i, x_i) in enumerate(history):
        weight = math.prod((speed - v_m) / (v_i - v_m) for m, v_m in enumerate(speeds) if m != i)
        lam = lam + weight * lam_i
        vec = vec + weight * x_i
    return lam, vec


def _apply(a, x):
    """A x for a batch of real (or complex) A (b, n, n) and complex x (b, n), by matmul."""
    if np.iscomplexobj(a):
        return np.matmul(a, x[..., None])[..., 0]
    split = np.matmul(a, np.stack([x.real, x.imag], axis=-1))
    return split[..., 0] + 1j * split[..., 1]


def _residual(pencil, lam, x):
    """Residual vectors r = A x - lambda E x and their componentwise backward error.

    The error is max_i |r_i| / (|A| |x| + |lambda| |E| |x|)_i (E = I for the standard
    problem): independent of how the rows are scaled (tyre forces in N next to angles in rad).
    """
    a, e, abs_a, abs_e = pencil
    ex = x if e is None else _apply(e, x)
    r = _apply(a, x) - lam[:, None] * ex
    size = np.abs(x)
    scale = np.matmul(abs_a, size[..., None])[..., 0] + np.abs(lam)[:, None] * (
        size if abs_e is None else np.matmul(abs_e, size[..., None])[..., 0])
    error = np.divide(np.abs(r), scale, out=np.zeros(r.shape), where=scale > 0)
    error[(scale == 0) & (r != 0)] = np.inf
    return r, ex, error.max(axis=1)


def _newton_step(pencil, lam, x, c, r, ex):
    """One bordered Newton step for a batch; r = A x - lam E x and ex = E x, (b, n)."""
    a, e = pencil[:2]
    b, n = x.shape
    jac = np.empty((b, n + 1, n + 1), dtype=complex)
    if e is None:
        jac[:, :n, :n] = a
        jac.reshape(b, -1)[:, 0:n * (n + 2):n + 2] -= lam[:, None]  # diagonal of the A block
    else:  # A - lambda E, real and imaginary parts written in place (no complex temporaries)
        block = jac[:, :n, :n]
        np.multiply(e, -lam.real[:, None, None], out=block.real)
        block.real += a
        np.multiply(e, -lam.imag[:, None, None], out=block.imag)
    jac[:, :n, n] = -ex
    jac[:, n, :n] = np.conj(c)
    jac[:, n, n] = 0.0
    rhs = np.empty((b, n + 1, 1), dtype=complex)
    rhs[:, :n, 0] = -r
    rhs[:, n, 0] = 1.0 - np.sum(np.conj(c) * x, axis=1)
    step = np.linalg.solve(jac, rhs)[..., 0]
    return lam + step[:, n], x + step[:, :n]


def _subset(pencil, part):
    return tuple(None if m is None else m[part] for m in pencil)


def _correct(e, a, lam, x, c, tol, max_iter):
    """Newton iterations on the batch until each member's residual <= tol."""
    pencil = (a, e, np.abs(a), None if e is None else np.abs(e))
    r, ex, res = _residual(pencil, lam, x)
    iters = np.zeros(lam.shape, dtype=int)
    for _ in range(max_iter):
        active = np.flatnonzero(res > tol)
        if active.size == 0:
            break
        part = slice(None) if active.size == lam.size else active
        sub = pencil if active.size == lam.size else _subset(pencil, part)
        lam[part], x[part] = _newton_step(sub, lam[part], x[part], c[part], r[part], ex[part])
        r[part], ex[part], res[part] = _residual(sub, lam[part], x[part])
        iters[part] += 1
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
    matrices : array (runs, speeds, n, n) or (speeds, n, n), a tuple (E, A) of such arrays,
        or a callable
        State matrices A [1/s], or the descriptor pencil (E, A) of E x' = A x; a callable
        ``matrices(j)`` returns A or (E, A), each (runs, n, n), for speed index j (nothing is
        stored for all speeds at once).
    eigenvalues0 : array (runs, modes) complex
        Eigenvalues at the first speed [1/s] (e.g. from :func:`nearest_eigenpairs`).
    eigenvectors0 : array (runs, n, modes) complex
        Matching eigenvectors (any scale).
    speeds : array (speeds,), optional
        Speeds [m/s] (used by the predictor); default equally spaced.
    n_speeds : int, optional
        Number of speeds when ``matrices`` is callable and ``speeds`` is not given.
    tol : float
        Tolerance on the componentwise backward error
        max_i |A x - lambda E x|_i / (|A| |x| + |lambda| |E| |x|)_i (E = I if not given).
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
    lam, x, iters, res = _correct(*_per_mode(get(0), modes), lam, x, x.copy(), tol, max_iter)
    out = _Recorder(runs, n_speeds, n, modes, keep_vectors)
    out.store(0, lam, x, iters, res, np.ones_like(res))
    history = [(grid[0], lam.copy(), x.copy())]
    for j in range(1, n_speeds):
        lam, x, iters, res = _step(_per_mode(get(j), modes), history, grid[j], tol, max_iter)
        c = history[-1][2]
        out.store(j, lam, x, iters, res, mac(c[..., None], x[..., None])[:, 0])
        history = (history + [(grid[j], lam.copy(), x.copy())])[-_HISTORY:]
    return out.result(tol)


def _step(pencil, history, speed, tol, max_iter):
    """Eigenpairs at the next speed: Newton from the extrapolated pairs; members that do not
    converge start again from the previous pairs (a safer, if slower, start)."""
    e, a = pencil
    c = history[-1][2]
    lam_p, x_p = _extrapolate(history, speed)
    x_p = x_p / np.sum(np.conj(c) * x_p, axis=1, keepdims=True)
    lam, x, iters, res = _correct(e, a, lam_p, x_p, c, tol, max_iter)
    failed = np.flatnonzero(res > tol)
    if failed.size and len(history) > 1:
        sub = (None if e is None else e[failed], a[failed])
        retry = _correct(*sub, history[-1][1][failed].copy(), c[failed].copy(), c[failed],
                         tol, max_iter)
        better = retry[3] < res[failed]
        keep = failed[better]
        lam[keep], x[keep], res[keep] = retry[0][better], retry[1][better], retry[3][better]
        iters[failed] += retry[2]
    x /= np.linalg.norm(x, axis=1, keepdims=True)
    return lam, x, iters, res


def _per_mode(pencil, modes):
    """Repeat each run's (E, A) once per tracked mode (the flattened batch order)."""
    e, a = pencil
    return (None if e is None else np.repeat(e, modes, axis=0)), np.repeat(a, modes, axis=0)


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
