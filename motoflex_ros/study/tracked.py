"""A study function that tracks chosen modes (weave, wobble) of a vehicle over speed.

This is the plug between the vehicle engine and the study runner: the vehicle supplies
``state_matrices(values, speed) -> (runs, n, n)``, the state matrix A [1/s] of every run at
one speed [m/s] for the stiffnesses ``values`` ({factor: array (runs,)} [N m/rad]), and a
``start(A0) -> (eigenvalues (runs, modes), eigenvectors (runs, n, modes))`` that picks the
modes at the first speed (by mode shape, for weave and wobble). The modes are then followed
over the speed grid by eigenpair continuation (:mod:`motoflex_ros.study.continuation`).
"""
from dataclasses import dataclass, field

import numpy as np

from motoflex_ros.errors import ModelError
from motoflex_ros.study.continuation import continue_eigenpairs, nearest_eigenpairs

__all__ = ["NearestTargets", "TrackedModeStudy"]


@dataclass(frozen=True)
class NearestTargets:
    """Start eigenpairs: the eigenvalues nearest to fixed targets [1/s], one per mode."""

    targets: tuple

    def __call__(self, matrices):
        return nearest_eigenpairs(matrices, np.asarray(self.targets, dtype=complex))


@dataclass(frozen=True)
class TrackedModeStudy:
    """Study function {factor: array (runs,)} -> {mode: eigenvalues (runs, speeds)}.

    state_matrices: callable (values, speed [m/s]) -> (runs, n, n) [1/s]; speeds: grid [m/s];
    start: callable A0 -> start eigenpairs, one per mode, in the order of ``modes``; modes:
    output names; tol: continuation residual tolerance; min_step_mac: below this MAC between
    consecutive eigenvectors the grid is too coarse to trust the tracking (ModelError).
    Also returns "<mode>_step_mac" (runs,): the smallest MAC seen over the sweep.
    """

    state_matrices: object
    speeds: tuple
    start: object
    modes: tuple = ("weave", "wobble")
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
