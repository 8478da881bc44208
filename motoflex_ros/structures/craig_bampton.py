"""Craig-Bampton reduction of a sparse structural model.

Craig & Bampton, "Coupling of substructures for dynamic analyses", AIAA J. 6(7), 1968; used in
the paper's Appendix (20 fixed-interface modes per body, content up to 600 Hz). Partition the
DOFs into boundary b (all DOFs of the interface nodes, kept physical) and interior i:

    u = [u_b; u_i] = T [u_b; eta],   T = [[1, 0], [Psi, Phi]],
    Psi = -K_ii^-1 K_ib (static constraint modes),  K_ii Phi = M_ii Phi Omega^2 (fixed-interface
    normal modes, mass-normalised).

One sparse factorisation of K_ii (:func:`motoflex_ros.structures.sparse_solver.factorize_spd`:
MKL PARDISO's Cholesky when pypardiso is installed, else scipy's SuperLU) serves both the
constraint modes (all boundary columns in one solve) and the shift-invert eigsh (sigma = 0,
OPinv = K_ii^-1); it is freed before the reduced matrices are formed. The reduction carries no
damping matrix, only the ratio zeta (one for all modes, or one per mode): the clamped reduced
model gives each of its own modes its ratio
(:func:`motoflex_ros.structures.clamped.modal_damping_matrix`), which damping on the
fixed-interface modes alone would not (the loaded end's boundary DOFs would stay undamped).
"""
from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from motoflex_ros.config import shown
from motoflex_ros.errors import ModelError
from motoflex_ros.structures.sparse_solver import factorize_spd

__all__ = ["N_MODES", "F_MAX_HZ", "CraigBamptonModel", "craig_bampton", "interior_blocks",
           "fixed_interface_modes", "checked_damping_ratio"]

N_MODES = 20
"""Fixed-interface normal modes kept per body, at most: the paper's Appendix A (Table A.1)."""
F_MAX_HZ = 600.0
"""No fixed-interface mode above this frequency [Hz] is kept: the paper's Appendix A."""


@dataclass(frozen=True)
class CraigBamptonModel:
    """Reduced matrices in coordinates (u_b, eta): boundary DOFs first, then modal amplitudes.

    M [kg..], K [N/m..] dense (n_b + n_m square); ``transform`` (sparse-dense,
    n_full x (n_b + n_m)) maps reduced coordinates to the full model's DOFs; ``boundary`` the
    full-model indices of the boundary DOFs; ``frequencies_hz`` the kept fixed-interface modal
    frequencies [Hz]; ``zeta`` the modal damping ratio [-] the reduced models are given: a
    float for every mode, or a tuple with one ratio per mode of the clamped reduced model
    (ascending frequency).
    """

    M: np.ndarray
    K: np.ndarray
    transform: np.ndarray
    boundary: np.ndarray
    frequencies_hz: np.ndarray
    zeta: object

    @property
    def n_modes(self):
        """Number of kept fixed-interface modes."""
        return len(self.frequencies_hz)


def interior_blocks(K, M, boundary):
    """(interior indices, K_ii, M_ii, K_ib dense) of (K, M) for the ``boundary`` DOFs, each
    block sliced straight from K and M (no full-size temporary)."""
    K, M = sp.csc_matrix(K), sp.csc_matrix(M)
    interior = np.setdiff1d(np.arange(K.shape[0]), boundary)
    k_ib = K[:, boundary].tocsr()[interior].toarray()
    return (interior, _principal(K, interior), _principal(M, interior), k_ib)


def _principal(matrix, keep):
    """The principal submatrix matrix[keep][:, keep] (CSC) via one selection product."""
    n = matrix.shape[0]
    select = sp.csc_matrix((np.ones(len(keep)), (keep, np.arange(len(keep)))),
                           shape=(n, len(keep)))
    return (select.T @ matrix @ select).tocsc()


def fixed_interface_modes(k_ii, m_ii, factor, n_modes, f_max_hz):
    """Lowest fixed-interface modes up to f_max_hz (at most n_modes), mass-normalised:
    (frequencies [Hz], Phi (n_i, n_kept)). ``factor`` is K_ii's :class:`SparseFactor`."""
    n_int = k_ii.shape[0]
    if n_modes <= 0 or n_int == 0:
        return np.zeros(0), np.zeros((n_int, 0))
    if n_modes >= n_int - 1 or n_int < 200:
        w2, phi = sla.eigh(k_ii.toarray(), m_ii.toarray())
    else:
        # a fixed start vector makes ARPACK, and so the reduced model, the same in every process
        start = np.linspace(1.0, 2.0, n_int)
        # shift-invert about 0: ARPACK uses only OPinv and M, so A is the factor's shape alone
        w2, phi = spla.eigsh(factor.operator(), k=n_modes, M=m_ii, sigma=0.0,
                             OPinv=factor.operator(), which="LM", v0=start)
    order = np.argsort(w2)
    w2, phi = w2[order], phi[:, order]
    freq = np.sqrt(np.maximum(w2, 0.0)) / (2 * np.pi)
    keep = np.flatnonzero(freq <= f_max_hz)[:n_modes]
    phi = phi[:, keep]
    phi = phi / np.sqrt(np.einsum("ij,ij->j", phi, m_ii @ phi))
    # sign convention: the largest entry of every mode is positive
    largest = phi[np.argmax(np.abs(phi), axis=0), np.arange(phi.shape[1])]
    return freq[keep], phi * np.where(largest < 0, -1.0, 1.0)


def craig_bampton(K, M, boundary, n_modes=N_MODES, f_max_hz=F_MAX_HZ, zeta=0.01,
                  solver="auto"):
    """Craig-Bampton reduction of (K, M) keeping ``boundary`` DOFs physical.

    Parameters
    ----------
    K, M : sparse (n, n)
        Stiffness [N/m, N, N m/rad] and mass [kg, kg m, kg m^2] of the full model.
    boundary : array of int
        Full-model indices of the boundary (interface) DOFs.
    n_modes : int
        Maximum number of fixed-interface normal modes kept (default 20).
    f_max_hz : float
        No mode above this frequency is kept [Hz] (default 600).
    zeta : float or sequence of float
        Modal damping ratio [-] in [0, 1) (default 0.01: 1 % on every mode), or one ratio per
        mode of the clamped reduced model in ascending frequency (issue 3: "modal damping ratio
        per mode"); carried to the reduced models built from this one
        (:func:`motoflex_ros.structures.clamped.reduce_clamped`, which checks the length).
    solver : {'auto', 'pardiso', 'superlu'}
        Sparse factorisation of K_ii (:func:`~motoflex_ros.structures.sparse_solver.factorize_spd`;
        'auto': PARDISO when pypardiso imports). The results agree to round-off.

    """
    K, M = sp.csc_matrix(K), sp.csc_matrix(M)
    n = K.shape[0]
    boundary = np.asarray(boundary, int)
    interior, k_ii, m_ii, k_ib = interior_blocks(K, M, boundary)
    with factorize_spd(k_ii, solver) as factor:
        psi = -factor.solve(k_ib) if len(interior) else np.zeros((0, len(boundary)))
        del k_ib
        freq, phi = fixed_interface_modes(k_ii, m_ii, factor, n_modes, f_max_hz)
    del k_ii, m_ii
    nb, nm = len(boundary), len(freq)
    transform = np.zeros((n, nb + nm))
    transform[boundary, np.arange(nb)] = 1.0
    transform[interior, :nb] = psi
    transform[interior, nb:] = phi
    k_red = transform.T @ (K @ transform)
    m_red = transform.T @ (M @ transform)
    k_red, m_red = 0.5 * (k_red + k_red.T), 0.5 * (m_red + m_red.T)
    return CraigBamptonModel(M=m_red, K=k_red, transform=transform,
                             boundary=boundary, frequencies_hz=freq,
                             zeta=checked_damping_ratio(zeta))


def checked_damping_ratio(zeta):
    """A modal damping ratio [-] as a float, or a tuple of per-mode ratios; ModelError unless
    every ratio is a finite number in [0, 1) (underdamped) and a list is not empty."""
    values = np.atleast_1d(np.asarray(zeta, float))
    if values.ndim != 1 or values.size == 0:
        raise ModelError(f"damping ratio: expected a number or a non-empty list, got "
                         f"{shown(zeta)}")
    bad = [float(v) for v in values if not (np.isfinite(v) and 0.0 <= v < 1.0)]
    if bad:
        raise ModelError(f"damping ratio {bad[0]:g} is out of the allowed range [0, 1)")
    return float(values[0]) if np.ndim(zeta) == 0 else tuple(map(float, values))
