"""One sparse factorisation of a symmetric positive definite stiffness, reused for every solve.

The Craig-Bampton reduction (:mod:`motoflex_ros.structures.craig_bampton`) needs K_ii^-1 twice:
for the constraint modes (many right-hand sides) and inside the shift-invert eigensolver
(one right-hand side per Lanczos step). Above ~1e5 DOFs the factorisation dominates, and
scipy's SuperLU (a general LU) does not finish a 2e5-DOF solid in minutes (issue 15). So:

* MKL PARDISO through the ``pypardiso`` wheel's ctypes binding, real symmetric positive
  definite (mtype 2: a sparse Cholesky L L^T of the upper triangle only, METIS nested
  dissection ordering), factorised once (phases 11 + 22), then solved with phase 33 alone:
  pypardiso's own ``solve`` would copy, hash or compare the matrix on every call and
  re-factorise when it thinks it changed; here the factor is the only state.
* scipy's SuperLU in symmetric mode when pypardiso (or its MKL) is not importable.

MKL's thread count is pinned for the calls (``threads``; default the MKL_NUM_THREADS
environment variable, else 1), never the machine's core count: the results then depend on the
thread count only through round-off.
"""
import ctypes
import os
from functools import lru_cache

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from motoflex_ros.errors import ModelError

__all__ = ["factorize_spd", "pardiso_available", "SparseFactor", "PARDISO_MIN_SIZE"]

PARDISO_MIN_SIZE = 10_000
"""'auto' takes PARDISO from this many unknowns on, SuperLU below. Below it SuperLU is as fast
or faster (Craig-Bampton of a quadratic-tetrahedron box: 3,675 DOFs 0.14 s against PARDISO's
0.59 s; 19,683 DOFs 3.4 against 1.5 s; 61,347 DOFs 34 against 11 s) and its result does not
depend on where the arrays sit in memory: MKL's kernels round differently with the alignment of
their inputs, which made the shipped swingarm's reduction differ by 7e-12 between a node process
and the process that identified it offline, where the rig promises 1e-12 (bags replay
bit-identically). Large meshes, PARDISO's purpose, carry no such promise."""

# PARDISO error codes (oneMKL reference, "pardiso"): the ones a stiffness can cause
_PARDISO_ERRORS = {-1: "input inconsistent", -2: "not enough memory",
                   -3: "reordering problem", -4: "zero or negative pivot",
                   -7: "diagonal matrix is singular", -8: "32-bit integer overflow",
                   -9: "not enough memory for out-of-core"}


def _singular(detail):
    return ModelError(f"the interior stiffness is singular ({detail}); is the structure "
                      "connected and held by its interface nodes?")


def default_threads():
    """MKL threads for the solver: MKL_NUM_THREADS when set, else 1 (deterministic)."""
    try:
        return max(1, int(os.environ.get("MKL_NUM_THREADS", "1")))
    except ValueError:
        return 1


@lru_cache(maxsize=1)
def _mkl_binding():
    """The ctypes binding of MKL that pypardiso makes (its library lookup spawns processes:
    done once)."""
    import pypardiso
    return pypardiso.PyPardisoSolver(mtype=2)


def pardiso_available():
    """True when pypardiso imports and finds MKL's runtime library."""
    try:
        import pypardiso  # noqa: F401  (not cached: a blocked import must count)
        _mkl_binding()
    except (ImportError, OSError):
        return False
    return True


class SparseFactor:
    """A factorised symmetric positive definite matrix A: ``solve(b)`` = A^-1 b for b of shape
    (n,) or (n, k) (all k right-hand sides in one call); ``operator()`` the same as a
    scipy LinearOperator (the OPinv of a shift-invert eigsh); ``free()`` releases the factor.
    ``solver`` is 'pardiso' or 'superlu'; ``factor_entries`` the stored entries of the factor.
    """

    solver = ""
    factor_entries = 0

    def __init__(self, shape):
        self.shape = shape

    def operator(self):
        """The solve as a LinearOperator (symmetric: matvec = rmatvec)."""
        return spla.LinearOperator(self.shape, matvec=self.solve, rmatvec=self.solve,
                                   matmat=self.solve, dtype=float)

    def free(self):
        """Release the factor's memory (a no-op for SuperLU: garbage collection does it)."""

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.free()


class _SuperLUFactor(SparseFactor):
    solver = "superlu"

    def __init__(self, matrix):
        super().__init__(matrix.shape)
        try:
            self._lu = spla.splu(sp.csc_matrix(matrix), permc_spec="MMD_AT_PLUS_A",
                                 diag_pivot_thresh=0.0, options={"SymmetricMode": True})
        except RuntimeError as exc:
            raise _singular(exc) from None
        self.factor_entries = self._lu.L.nnz + self._lu.U.nnz

    def solve(self, b):
        return self._lu.solve(np.asarray(b, float))

    def free(self):
        self._lu = None


class _PardisoFactor(SparseFactor):
    """MKL PARDISO, mtype 2, zero-based CSR of the upper triangle, phase 33 solves."""

    solver = "pardiso"
    MTYPE = 2   # real symmetric positive definite

    def __init__(self, matrix, threads):
        super().__init__(matrix.shape)
        upper = sp.triu(sp.csr_matrix(matrix), format="csr")
        upper.sum_duplicates()
        upper.sort_indices()
        if np.any(np.diff(upper.indptr) == 0):
            raise _singular("a row without entries")
        self._data = np.ascontiguousarray(upper.data, float)
        self._ia = upper.indptr.astype(np.int32)
        self._ja = upper.indices.astype(np.int32)
        del upper
        binding = _mkl_binding()
        self._lib = binding.libmkl
        self._call = binding._mkl_pardiso
        self._pt = np.zeros(64, np.int64)
        self._iparm = np.zeros(64, np.int32)
        self._iparm[0] = 1    # iparm(1): not the defaults
        self._iparm[1] = 2    # iparm(2): METIS nested dissection (serial: same order always)
        self._iparm[7] = 0    # iparm(8): no iterative refinement (a Cholesky needs none)
        self._iparm[9] = 13   # iparm(10): pivot perturbation 1e-13 (indefinite types only)
        self._iparm[17] = -1  # iparm(18): report the factor's nonzeros
        self._iparm[34] = 1   # iparm(35): zero-based indices
        self._threads = threads
        self._alive = True
        self._run(12, np.zeros((self.shape[0], 1)))
        self.factor_entries = int(self._iparm[17])

    def _run(self, phase, b):
        b = np.asfortranarray(b, float)
        x = np.zeros_like(b)
        error = ctypes.c_int32(0)
        i32 = ctypes.POINTER(ctypes.c_int32)
        f64 = ctypes.POINTER(ctypes.c_double)
        previous = self._lib.MKL_Set_Num_Threads_Local(ctypes.c_int(self._threads))
        try:
            self._call(self._pt.ctypes.data_as(ctypes.POINTER(ctypes.c_int64)),
                       ctypes.byref(ctypes.c_int32(1)), ctypes.byref(ctypes.c_int32(1)),
                       ctypes.byref(ctypes.c_int32(self.MTYPE)),
                       ctypes.byref(ctypes.c_int32(phase)),
                       ctypes.byref(ctypes.c_int32(self.shape[0])),
                       self._data.ctypes.data_as(f64), self._ia.ctypes.data_as(i32),
                       self._ja.ctypes.data_as(i32), None,
                       ctypes.byref(ctypes.c_int32(b.shape[1] if b.ndim == 2 else 1)),
                       self._iparm.ctypes.data_as(i32), ctypes.byref(ctypes.c_int32(0)),
                       b.ctypes.data_as(f64), x.ctypes.data_as(f64), ctypes.byref(error))
        finally:
            self._lib.MKL_Set_Num_Threads_Local(ctypes.c_int(previous))
        if error.value == -4 or error.value == -7:
            self.free()
            raise _singular(f"PARDISO: {_PARDISO_ERRORS[error.value]}")
        if error.value != 0:
            self.free()
            raise ModelError(f"PARDISO failed with error {error.value}: "
                             f"{_PARDISO_ERRORS.get(error.value, 'see the oneMKL reference')}")
        return x

    def solve(self, b):
        if not self._alive:
            raise ModelError("the factorisation was freed")
        b = np.asarray(b, float)
        if b.shape[0] != self.shape[0]:
            raise ValueError(f"right-hand side has {b.shape[0]} rows, expected {self.shape[0]}")
        if b.ndim == 2 and b.shape[1] == 0:
            return np.zeros_like(b)
        x = self._run(33, b)
        return np.ascontiguousarray(x)

    def free(self):
        if self._alive:
            self._alive = False
            self._run(-1, np.zeros((self.shape[0], 1)))

    def __del__(self):
        try:
            self.free()
        except Exception:   # interpreter shutdown: MKL may be gone already
            pass


def factorize_spd(matrix, solver="auto", threads=None):
    """Factorise a sparse symmetric positive definite ``matrix`` once.

    Parameters
    ----------
    matrix : sparse (n, n)
        Symmetric positive definite (e.g. an interior stiffness K_ii [N/m..]); only its upper
        triangle is read by PARDISO.
    solver : {'auto', 'pardiso', 'superlu'}
        'auto': PARDISO when pypardiso imports and the matrix has at least PARDISO_MIN_SIZE
        rows, else SuperLU.
    threads : int or None
        MKL threads during the factorisation and solves (default :func:`default_threads`).

    Returns
    -------
    SparseFactor
        Raises ModelError when the matrix is singular (or not positive definite).

    """
    if solver not in ("auto", "pardiso", "superlu"):
        raise ValueError(f"solver must be 'auto', 'pardiso' or 'superlu', got {solver!r}")
    if solver == "auto":
        large = matrix.shape[0] >= PARDISO_MIN_SIZE
        solver = "pardiso" if large and pardiso_available() else "superlu"
    if solver == "superlu" or matrix.shape[0] == 0:
        return _SuperLUFactor(matrix)
    if not pardiso_available():
        raise ModelError("solver 'pardiso' needs the pypardiso package with MKL "
                         "(pip install pypardiso); 'auto' falls back to SuperLU")
    return _PardisoFactor(matrix, default_threads() if threads is None else int(threads))
