"""Clamped-component solvers on the reduced model: static, modal (with mode labels), state space.

The component frame is the paper's (Sect. 4.2, Fig. 2): clamp at O, symmetry plane x-z, lateral
load F_y at the loaded end q0. Modes are labelled from their shape at the loaded end, never from
their order: a mode whose loaded-end motion is mainly in the x-z plane (u_x, u_z, theta_y) is
'in_plane'; otherwise the deformation axis of eqs. (1)-(7) applied to the modal displacement
decides: within 45 deg of the line O-q0 (beta near 0 or pi) it is 'torsion', else 'bending'.
A mode the loaded end hardly takes part in (a part vibrating on its own mount) is 'local'.
"""
from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla

from motoflex_ros.errors import ModelError
from motoflex_ros.lumped_stiffness.axis import axis_stiffness, deformation_axis
from motoflex_ros.spatial import skew

__all__ = ["ReducedComponent", "StaticResult", "label_mode", "end_pose", "modal_damping_matrix",
           "state_space", "reduce_clamped", "end_share", "eigenspaces", "DEGENERATE_RTOL",
           "check_one_ratio_per_eigenspace", "clamped_frequencies"]

LATERAL = (1, 3, 5)     # u_y, theta_x, theta_z at the loaded end
PLANAR = (0, 2, 4)      # u_x, u_z, theta_y
LOCAL_SHARE = 0.2       # loaded-end amplitude below 20 % of the largest node motion: 'local'
DEGENERATE_RTOL = 1e-6  # modes closer than this (relative) share one eigenspace


def end_pose(end_motion, q0, scale=1.0):
    """Pose (q [m], R) of the loaded end after the motion ``scale * end_motion``.

    end_motion = (u_x, u_y, u_z, theta_x, theta_y, theta_z) [m, rad]; R = expm(skew(theta)).
    """
    u = scale * np.asarray(end_motion[:3], float)
    theta = scale * np.asarray(end_motion[3:], float)
    return np.asarray(q0, float) + u, sla.expm(skew(theta))


def _small_scale(end_motion, q0, size=1e-6):
    """Scale that makes the larger of |u| and L |theta| equal to size * L."""
    length = np.linalg.norm(q0)
    amp = max(np.linalg.norm(end_motion[:3]), length * np.linalg.norm(end_motion[3:]))
    return size * length / amp


def end_share(node_motion, end_motion, q0):
    """How much the loaded end takes part in a mode: the ``end_share`` of :func:`label_mode`.

    Parameters
    ----------
    node_motion : array (6 n_nodes,)
        The mode's motion of all nodes (ux, uy, uz, rx, ry, rz each) [m, rad].
    end_motion : array (6,)
        The loaded end's motion (u, theta) [m, rad].
    q0 : array (3,)
        The loaded end [m]; L = |q0| weighs the rotations.

    Returns
    -------
    float
        max(|u|, L |theta|) at the loaded end over the largest node translation [-].

    """
    nodes = np.asarray(node_motion).reshape(-1, 6)
    end = np.asarray(end_motion)
    amp = max(np.linalg.norm(end[:3]), np.linalg.norm(q0) * np.linalg.norm(end[3:]))
    return amp / max(np.max(np.linalg.norm(nodes[:, :3], axis=1)), 1e-300)


def label_mode(end_motion, q0, end_share=1.0):
    """'torsion', 'bending', 'in_plane' or 'local' from a mode's loaded-end motion (6,).

    end_motion = (u, theta) [m, rad]. ``end_share`` is the loaded end's amplitude over the
    largest nodal translation of the mode; below LOCAL_SHARE the mode is 'local' (a part
    vibrating on its own, e.g. a rigid part on its mount, hardly seen at the loaded end).
    Lateral content: (u_y, L theta_x, L theta_z); planar content (u_x, u_z, L theta_y), with
    L = |q0|. Mainly planar -> 'in_plane'. Otherwise the mode's deformation axis (eqs. 1-7 on
    q = q0 + eps u, R = expm(eps [theta]x)) within 45 deg of O-q0 is 'torsion', else 'bending'.
    """
    if end_share < LOCAL_SHARE:
        return "local"
    m = np.asarray(end_motion, float)
    length = np.linalg.norm(q0)
    weights = np.array([1.0, 1.0, 1.0, length, length, length])
    if np.linalg.norm((m * weights)[list(LATERAL)]) < np.linalg.norm((m * weights)[list(PLANAR)]):
        return "in_plane"
    axis = mode_axis(m, q0)
    return "torsion" if (axis.beta < np.pi / 4 or axis.beta > 3 * np.pi / 4) else "bending"


def mode_axis(end_motion, q0):
    """Deformation axis (eqs. 1-7) of a small motion of the loaded end (mode shape)."""
    q, rot = end_pose(end_motion, q0, _small_scale(end_motion, q0))
    with np.errstate(divide="ignore", invalid="ignore"):   # axis parallel to O-q0: l = nan
        return deformation_axis(q, rot, q0)


def eigenspaces(omega, rtol=DEGENERATE_RTOL):
    """Eigenspaces of ascending natural frequencies ``omega`` [rad/s]: lists of mode indices.

    Modes whose frequencies lie within ``rtol`` (relative to the largest) of the first mode of
    their group form one eigenspace. Inside it the eigensolver may return any orthonormal basis
    (a symmetric tube's bending pairs: which of the two comes first depends on the BLAS
    kernel), so only what is the same for every basis has a meaning there.
    """
    omega = np.asarray(omega, float)
    scale = rtol * max(float(np.max(np.abs(omega), initial=0.0)), 1e-300)
    groups = []
    for i, w in enumerate(omega):
        if groups and abs(w - omega[groups[-1][0]]) <= max(scale, rtol * abs(w)):
            groups[-1].append(i)
        else:
            groups.append([i])
    return groups


def check_one_ratio_per_eigenspace(zeta, omega):
    """ModelError unless every eigenspace of ``omega`` gets one damping ratio from ``zeta``."""
    for group in eigenspaces(omega):
        ratios = [float(zeta[i]) for i in group]
        if max(ratios) - min(ratios) > 1e-12:
            modes = ", ".join(str(i + 1) for i in group)
            raise ModelError(f"damping ratio: modes {modes} share one frequency "
                             f"({omega[group[0]] / (2 * np.pi):.6g} Hz, a degenerate "
                             f"eigenspace whose mode shapes are defined only up to a rotation), "
                             f"so they need one ratio; got {', '.join(f'{r:g}' for r in ratios)}")


def clamped_frequencies(M, K):
    """Natural frequencies [rad/s] of (M, K), ascending."""
    return np.sqrt(np.maximum(sla.eigh(K, M, eigvals_only=True), 0.0))


def modal_damping_matrix(M, K, zeta):
    """Damping matrix giving mode i of (M, K) the ratio zeta_i [N s/m..].

    C = M Phi diag(2 zeta_i omega_i) Phi^T M with Phi mass-normalised (Phi^T M Phi = 1), modes
    in ascending frequency. ``zeta`` [-]: one ratio for all modes, or one per mode (ModelError
    when the count differs from the number of modes, or when the modes of one degenerate
    eigenspace get different ratios: the damping would then depend on which basis of the
    eigenspace the eigensolver returned). With one ratio per eigenspace C does not depend on
    that basis: the eigenspace enters only through its projector Phi_g Phi_g^T.
    """
    w2, phi = sla.eigh(K, M)
    omega = np.sqrt(np.maximum(w2, 0.0))
    if np.ndim(zeta) and len(zeta) != len(omega):
        raise ModelError(f"damping ratio: {len(zeta)} values given, but the clamped reduced "
                         f"model has {len(omega)} modes (its free interface DOFs plus the "
                         f"kept fixed-interface modes); give one value or {len(omega)}")
    if np.ndim(zeta):
        check_one_ratio_per_eigenspace(zeta, omega)
    zeta = np.asarray(zeta, float)
    mphi = M @ phi
    return (mphi * (2 * zeta * omega)) @ mphi.T


@dataclass(frozen=True)
class StaticResult:
    """Static response to a lateral force at the loaded end (eqs. 1-8).

    force [N]; end_motion (u, theta) [m, rad]; axis (l, beta, b); k about the axis [N m/rad].
    """

    force: float
    end_motion: np.ndarray
    axis: object
    k: float


@dataclass(frozen=True)
class ReducedComponent:
    """Clamped Craig-Bampton model of a component: M [kg..], K [N/m..], C [N s/m..] (dense).

    Coordinates: the physical DOFs of the non-clamped interface nodes, then the modal
    amplitudes. ``end_dofs``: indices of the loaded end's (ux, uy, uz, rx, ry, rz). ``q0``: the
    loaded end in the component frame [m]. ``frequencies_hz`` and ``mode_labels``: modes of the
    clamped reduced model, ascending; ``mode_shapes`` their mass-normalised vectors (columns).
    ``transform`` maps reduced coordinates to all node DOFs (6 per node, ux..rz); see
    :meth:`node_displacements`.
    """

    name: str
    M: np.ndarray
    K: np.ndarray
    C: np.ndarray
    end_dofs: np.ndarray
    q0: np.ndarray
    frequencies_hz: np.ndarray
    mode_labels: tuple
    mode_shapes: np.ndarray
    transform: np.ndarray
    n_modes: int

    @property
    def n(self):
        """Number of reduced coordinates."""
        return self.K.shape[0]

    def node_displacements(self, x):
        """Displacements (n_nodes, 6) [m, rad] of all nodes from reduced coordinates x."""
        return (self.transform @ np.asarray(x, float)).reshape(-1, 6)

    def end_load_vector(self, wrench):
        """Reduced load vector of a wrench (F_x, F_y, F_z, M_x, M_y, M_z) [N, N m] at the end."""
        f = np.zeros(self.n)
        f[self.end_dofs] = wrench
        return f

    def static_end_motion(self, wrench):
        """Loaded-end motion (u, theta) [m, rad] under a static wrench at the loaded end."""
        x = np.linalg.solve(self.K, self.end_load_vector(wrench))
        return x[self.end_dofs]

    def static_lateral(self, force=100.0):
        """Static test: F_y = ``force`` [N] at q0; axis from eqs. (1)-(7), k from eq. (8)."""
        motion = self.static_end_motion([0.0, force, 0.0, 0.0, 0.0, 0.0])
        q, rot = end_pose(motion, self.q0)
        axis = deformation_axis(q, rot, self.q0)
        return StaticResult(force=float(force), end_motion=motion, axis=axis,
                            k=float(axis_stiffness(force, q[1], axis.b)))

    def first_mode(self, label):
        """Index of the lowest mode with the given label, or None."""
        hits = [i for i, lab in enumerate(self.mode_labels) if lab == label]
        return hits[0] if hits else None

    def frequency(self, label):
        """Frequency [Hz] of the first mode with this label (NaN when there is none)."""
        i = self.first_mode(label)
        return float(self.frequencies_hz[i]) if i is not None else float("nan")

    def mode_axis(self, label):
        """Deformation axis (eqs. 1-7) of the first mode with this label."""
        i = self.first_mode(label)
        return mode_axis(self.mode_shapes[self.end_dofs, i], self.q0)

    def state_space(self):
        """(A, B) of x' = A x + B w, x = (q, q'), w the loaded-end wrench (:func:`state_space`)."""
        return state_space(self)

def state_space(reduced):
    """State-space model of a clamped reduced component under a loaded-end wrench.

    M q'' + C q' + K q = F w, F the columns of the loaded end's DOFs, written as
    x' = A x + B w with x = (q, q') and

        A = [[0, 1], [-M^-1 K, -M^-1 C]],   B = [[0], [M^-1 F]].

    Parameters
    ----------
    reduced : ReducedComponent (or any object with M, K, C and end_dofs)
        Mass [kg..], stiffness [N/m..] and damping [N s/m..] of the reduced coordinates q, and
        the indices of the loaded end's six DOFs among them.

    Returns
    -------
    A : ndarray (2n, 2n)
        State matrix [1/s, 1/s^2].
    B : ndarray (2n, 6)
        Input matrix for w = (F_x, F_y, F_z, M_x, M_y, M_z) [N, N m] at the loaded end.

    """
    n = reduced.K.shape[0]
    m_inv = np.linalg.inv(reduced.M)
    a = np.zeros((2 * n, 2 * n))
    a[:n, n:] = np.eye(n)
    a[n:, :n] = -m_inv @ reduced.K
    a[n:, n:] = -m_inv @ reduced.C
    b = np.zeros((2 * n, 6))
    b[n:, :] = m_inv[:, reduced.end_dofs]
    return a, b


def reduce_clamped(name, cb, keep, end_dofs, q0, expand):
    """ReducedComponent from a Craig-Bampton model by deleting clamped boundary coordinates.

    ``keep`` are reduced-coordinate indices kept (free boundary DOFs then all modal ones);
    ``expand`` (sparse) maps full-model DOFs to all node DOFs. Every mode of the clamped
    reduced model gets the Craig-Bampton model's damping ratio ``cb.zeta`` (one for all, or one
    per mode in ascending frequency: :func:`modal_damping_matrix`).
    """
    m = cb.M[np.ix_(keep, keep)]
    k = cb.K[np.ix_(keep, keep)]
    w2, phi = sla.eigh(k, m)
    freq = np.sqrt(np.maximum(w2, 0.0)) / (2 * np.pi)
    transform = np.asarray(expand @ cb.transform[:, keep])
    labels = tuple(label_mode(phi[end_dofs, j], q0,
                              end_share(transform @ phi[:, j], phi[end_dofs, j], q0))
                   for j in range(len(freq)))
    return ReducedComponent(name=name, M=m, K=k, C=modal_damping_matrix(m, k, cb.zeta),
                            end_dofs=np.asarray(end_dofs), q0=np.asarray(q0, float),
                            frequencies_hz=freq, mode_labels=labels, mode_shapes=phi,
                            transform=transform, n_modes=cb.n_modes)
