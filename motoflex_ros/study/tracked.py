"""A study function that tracks chosen modes (weave, wobble) of a vehicle over speed.

This is the plug between the vehicle engine and the study runner: the vehicle supplies
``state_matrices(values, speed) -> (runs, n, n)``, the state matrix A [1/s] of every run at
one speed [m/s] for the stiffnesses ``values`` ({factor: array (runs,)} [N m/rad]), and a
``start(A0) -> (eigenvalues (runs, modes), eigenvectors (runs, n, modes))`` that picks the
modes at the first speed (by mode shape, for weave and wobble). The modes are then followed
over the speed grid by eigenpair continuation (:mod:`motoflex_ros.study.continuation`).
``state_matrices`` may also return the descriptor pencil (E, A) of E x' = A x (massless
bodies make E singular).

A joint spring enters the linearized equations linearly (generalised force -k q), so for a
lumped-stiffness vehicle A(v; k) = A(v; k_nom) + sum_i (k_i - k_nom,i) D_i with constant
D_i = dA/dk_i. :class:`LinearStiffnessPencil` builds every run's pencil that way from one
nominal linearization (E(v), A(v) as speed polynomials, e.g. the vehicle engine's
LinearVehicle.E_coeffs / A_coeffs) and :func:`stiffness_directions` finds the D_i by
differences of the speed-independent coefficient A_0, checking the linearity;
:func:`check_pencil` checks the superposition against a direct linearization at another speed
(D_i constant only if the spring terms do not depend on speed).
"""
from dataclasses import dataclass, field

import numpy as np

from motoflex_ros.errors import ModelError
from motoflex_ros.study.continuation import continue_eigenpairs, nearest_eigenpairs
from motoflex_ros.vehicle.mode_names import STUDIED_MODES

__all__ = ["NearestTargets", "HomotopyStart", "TrackedModeStudy", "LinearStiffnessPencil",
           "stiffness_directions", "check_pencil", "pencil_study"]


@dataclass(frozen=True)
class NearestTargets:
    """Start eigenpairs: the eigenvalues nearest to fixed targets [1/s], one per mode."""

    targets: tuple

    def __call__(self, matrices):
        targets = np.asarray(self.targets, dtype=complex)
        if isinstance(matrices, tuple):
            return nearest_eigenpairs(matrices[1], targets, descriptor=matrices[0])
        return nearest_eigenpairs(matrices, targets)


@dataclass(frozen=True, eq=False)
class HomotopyStart:
    """Start eigenpairs continued from the nominal vehicle to each run's stiffnesses.

    nominal: the nominal A or pencil (E, A) at the first speed, each (n, n) (1 run); targets:
    approximate nominal eigenvalues, one per mode [1/s] (e.g. weave and wobble as the vehicle
    engine names them by mode shape); steps: continuation steps in t from the nominal (t = 0)
    to each run (t = 1), along A(t) = A_nom + t (A_run - A_nom). Unlike picking the nearest
    eigenvalue at each run, this keeps mode identity when a large variation moves two modes
    past each other.
    """

    nominal: object
    targets: tuple
    steps: int = 8

    def _nominal_pairs(self):
        if isinstance(self.nominal, tuple):
            e, a = (np.asarray(m)[None] for m in self.nominal)
            return nearest_eigenpairs(a, np.asarray(self.targets, complex), descriptor=e)
        return nearest_eigenpairs(np.asarray(self.nominal)[None],
                                  np.asarray(self.targets, complex))

    def __call__(self, matrices):
        lam, vec = self._nominal_pairs()
        pencil = isinstance(matrices, tuple)
        runs_ = [np.asarray(m) for m in (matrices if pencil else (matrices,))]
        nominal = [np.asarray(m) for m in (self.nominal if pencil else (self.nominal,))]
        runs = runs_[-1].shape[0]
        t = np.linspace(0.0, 1.0, self.steps + 1)

        def path(j):
            mats = tuple(m_nom + t[j] * (m_run - m_nom) for m_nom, m_run in zip(nominal, runs_))
            return mats if pencil else mats[0]

        result = continue_eigenpairs(path, np.repeat(lam, runs, 0), np.repeat(vec, runs, 0),
                                     speeds=t, keep_vectors=True)
        if not np.all(result.converged):
            raise ModelError("could not continue the modes from the nominal vehicle to a run; "
                             "use more homotopy steps")
        return result.eigenvalues[:, -1], result.eigenvectors[:, -1]


@dataclass(frozen=True)
class TrackedModeStudy:
    """Study function {factor: array (runs,)} -> {mode: eigenvalues (runs, speeds)}.

    state_matrices: callable (values, speed [m/s]) -> A (runs, n, n) [1/s] or a pencil (E, A);
    speeds: grid [m/s];
    start: callable A0 -> start eigenpairs, one per mode, in the order of ``modes``; modes:
    output names; tol: continuation residual tolerance; min_step_mac: below this MAC between
    consecutive eigenvectors the grid is too coarse to trust the tracking (ModelError).
    Also returns "<mode>_step_mac" (runs,): the smallest MAC seen over the sweep.
    """

    state_matrices: object
    speeds: tuple
    start: object
    modes: tuple = STUDIED_MODES
    tol: float = 1e-12
    min_step_mac: float = field(default=0.5)

    def __call__(self, values):
        speeds = np.asarray(self.speeds, dtype=float)
        lam0, vec0 = self.start(self.state_matrices(values, speeds[0]))
        if lam0.shape[1] != len(self.modes):
            raise ModelError(f"start gave {lam0.shape[1]} modes, expected {len(self.modes)}")
        result = continue_eigenpairs(lambda j: self.state_matrices(values, speeds[j]),
                                     lam0, vec0, speeds=speeds, tol=self.tol)
        if not np.all(result.converged):
            worst = float(result.residual.max())
            raise ModelError(f"mode tracking did not converge (relative residual {worst:.2e})")
        step_mac = result.step_mac.min(axis=1)
        if np.any(step_mac < self.min_step_mac):
            raise ModelError(f"mode tracking lost a mode between two speeds (MAC "
                             f"{step_mac.min():.2f}); use a finer speed grid")
        outputs = {mode: result.eigenvalues[:, :, i] for i, mode in enumerate(self.modes)}
        outputs.update({f"{mode}_step_mac": step_mac[:, i] for i, mode in enumerate(self.modes)})
        return outputs


@dataclass(frozen=True, eq=False)
class LinearStiffnessPencil:
    """Pencils E(v), A(v; k) of a vehicle whose joint stiffnesses are the factors.

    E_coeffs, A_coeffs: (degree + 1, n, n) speed-polynomial coefficients at the nominal
    stiffness (E(v) = sum_p v^p E_p); directions: {factor: D_i (n, n)} = dA/dk_i
    [1/s per N m/rad]; nominal: {factor: k_nom,i} [N m/rad]. Called as a study's
    ``state_matrices(values, speed)``, returns (E, A), each (runs, n, n).
    """

    E_coeffs: np.ndarray
    A_coeffs: np.ndarray
    directions: dict
    nominal: dict

    def __call__(self, values, speed):
        powers = float(speed) ** np.arange(len(self.A_coeffs))
        e = np.tensordot(powers, self.E_coeffs, axes=1)
        a = np.tensordot(powers, self.A_coeffs, axes=1)
        names = list(self.directions)
        delta = np.column_stack([np.asarray(values[f], float) - self.nominal[f] for f in names])
        stacked = np.stack([self.directions[f] for f in names])
        a_runs = a + np.tensordot(delta, stacked, axes=1)
        return np.broadcast_to(e, a_runs.shape), a_runs


def stiffness_directions(matrix_of, nominal, rel_step=0.1, tol=1e-8):
    """D_i = dM/dk_i of a matrix linear in each stiffness, by a difference, checked.

    Parameters
    ----------
    matrix_of : callable
        ``matrix_of({factor: k}) -> array`` (e.g. the speed-independent coefficient A_0 of a
        linearized vehicle with those joint stiffnesses [N m/rad]).
    nominal : mapping
        Nominal stiffness of every factor [N m/rad].
    rel_step : float
        The difference step, relative to the nominal value.
    tol : float
        Allowed relative mismatch of the opposite-side difference (linearity check).

    Returns
    -------
    {factor: D_i}

    """
    base = np.asarray(matrix_of(dict(nominal)), dtype=float)
    scale = max(float(np.max(np.abs(base))), 1.0)
    directions = {}
    for name, k in nominal.items():
        step = rel_step * float(k)
        up = np.asarray(matrix_of({**nominal, name: k + step}), dtype=float)
        down = np.asarray(matrix_of({**nominal, name: k - step}), dtype=float)
        directions[name] = (up - base) / step
        mismatch = float(np.max(np.abs(up + down - 2.0 * base))) / scale
        if mismatch > tol:
            raise ModelError(f"the matrix is not linear in stiffness {name} (relative "
                             f"mismatch {mismatch:.1e}); a linear stiffness pencil needs it")
    return directions


def check_pencil(pencil, reference, values, speed, tol=1e-8):
    """Raise ModelError unless ``pencil(values, speed)`` equals the direct ``reference``.

    Parameters
    ----------
    pencil : LinearStiffnessPencil
        The superposed pencils (nominal E(v), A(v) plus stiffness directions D_i).
    reference : callable
        ``reference({factor: k}, speed) -> (E, A)`` (n, n) of one direct linearization.
    values : mapping
        Stiffnesses [N m/rad] to compare at (one run).
    speed : float
        Speed [m/s]; away from the speed of the directions, so that a stiffness term that
        depends on speed (D_i not constant) shows up.
    tol : float
        Allowed mismatch relative to the largest entry of A.

    """
    e_run, a_run = pencil({f: np.array([float(k)]) for f, k in values.items()}, speed)
    e_ref, a_ref = (np.asarray(m, float) for m in reference(dict(values), speed))
    scale = max(float(np.max(np.abs(a_ref))), 1.0)
    mismatch = max(float(np.max(np.abs(e_run[0] - e_ref))),
                   float(np.max(np.abs(a_run[0] - a_ref)))) / scale
    if mismatch > tol:
        raise ModelError(f"the stiffness pencil differs from a direct linearization at "
                         f"{speed:g} m/s (relative mismatch {mismatch:.1e}): the stiffnesses "
                         f"enter A(v) other than through its speed-independent part A_0")


def pencil_study(e_coeffs, a_coeffs, matrix_of, nominal, speeds, targets,
                 modes=STUDIED_MODES, reference=None):
    """The study function of a linearized vehicle whose joint stiffnesses are the factors.

    Parameters
    ----------
    e_coeffs, a_coeffs : array (degree + 1, n, n)
        Speed-polynomial coefficients of E(v), A(v) at the nominal stiffness (e.g. the vehicle
        engine's LinearVehicle.E_coeffs, A_coeffs).
    matrix_of : callable
        ``matrix_of({factor: k}) -> A_0`` (n, n), the speed-independent coefficient with those
        stiffnesses [N m/rad] (one linearization per call; 13 calls for six factors).
    nominal : mapping
        Nominal stiffnesses [N m/rad].
    speeds : array
        Speed grid [m/s].
    targets : sequence of complex
        Nominal eigenvalues of the modes at ``speeds[0]`` [1/s], e.g. weave and wobble as the
        engine's modal sweep names them.
    modes : tuple of str
        Output names, in the order of ``targets``.
    reference : callable, optional
        ``reference({factor: k}, speed) -> (E, A)`` of a direct linearization; if given, the
        pencil is checked against it (:func:`check_pencil`) at the highest speed with every
        stiffness 10 % above nominal: the directions D_i = dA_0/dk_i describe A(v) at every
        speed only if the stiffness terms do not depend on speed.

    """
    directions = stiffness_directions(matrix_of, dict(nominal))
    pencil = LinearStiffnessPencil(np.asarray(e_coeffs), np.asarray(a_coeffs), directions,
                                   dict(nominal))
    if reference is not None:
        check_pencil(pencil, reference, {f: 1.1 * float(k) for f, k in nominal.items()},
                     float(np.max(speeds)))
    e0, a0 = pencil({f: np.array([float(k)]) for f, k in nominal.items()}, speeds[0])
    start = HomotopyStart(nominal=(e0[0], a0[0]), targets=tuple(targets))
    return TrackedModeStudy(state_matrices=pencil, speeds=tuple(np.asarray(speeds, float)),
                            start=start, modes=tuple(modes))
