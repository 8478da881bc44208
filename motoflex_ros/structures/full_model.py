"""The full (unreduced) finite-element model of a clamped component, for checking the reduced one.

The Craig-Bampton model keeps at most 20 fixed-interface modes and none above 600 Hz (issue 3);
a component whose fixed-interface modes all lie above the cap (e.g. the validation tube) keeps
none, and its clamped reduced model then carries only the static constraint modes, whose
frequencies can be far off. The full clamped model's lowest modes (sparse shift-invert eigsh,
sigma = 0, on the reduction's sparse factorisation,
:func:`motoflex_ros.structures.sparse_solver.factorize_spd`) are the reference the summary puts
beside the reduced model's.
"""
from dataclasses import dataclass

import numpy as np
import scipy.sparse.linalg as spla

from motoflex_ros.structures.clamped import end_share, label_mode
from motoflex_ros.structures.sparse_solver import factorize_spd

__all__ = ["FullModes", "full_clamped_matrices", "full_clamped_modes"]


@dataclass(frozen=True)
class FullModes:
    """Lowest modes of the full clamped model: frequencies [Hz] ascending and their labels
    ('torsion', 'bending', 'in_plane', 'local'; labelled as the reduced model's modes are)."""

    frequencies_hz: np.ndarray
    labels: tuple

    def frequency(self, label):
        """Frequency [Hz] of the lowest mode with this label (NaN when none is among them)."""
        hits = [f for f, lab in zip(self.frequencies_hz, self.labels) if lab == label]
        return float(hits[0]) if hits else float("nan")


def full_clamped_matrices(component):
    """(K [N/m..], M [kg..], assembled structure) of the full model with the clamps applied."""
    asm = component.clamped_assembled()
    return asm.K, asm.M, asm


def full_clamped_modes(component, n_modes=30):
    """FullModes: the ``n_modes`` lowest modes of the full clamped model of ``component``.

    Parameters
    ----------
    component : Component
        The clamped component (its clamp nodes fixed, all other DOFs free).
    n_modes : int
        Number of modes computed (fewer when the model has fewer DOFs).

    Returns
    -------
    FullModes
        Frequencies sqrt(eig(K, M)) / (2 pi) [Hz], each labelled from its loaded-end motion
        (:func:`motoflex_ros.structures.clamped.label_mode`).

    """
    k, m, asm = full_clamped_matrices(component)
    count = min(n_modes, k.shape[0] - 2)
    with factorize_spd(k) as factor:
        w2, phi = spla.eigsh(factor.operator(), k=count, M=m.tocsc(), sigma=0.0,
                             OPinv=factor.operator(), which="LM")
    order = np.argsort(w2)
    w2, phi = w2[order], phi[:, order]
    end = asm.node_dofs(component.loaded_end)
    q0 = component.q0
    labels = tuple(label_mode(phi[end, j], q0, end_share(asm.expand @ phi[:, j], phi[end, j],
                                                         q0))
                   for j in range(count))
    return FullModes(np.sqrt(np.maximum(w2, 0.0)) / (2 * np.pi), labels)
