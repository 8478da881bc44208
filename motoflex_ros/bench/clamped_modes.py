"""Modal analysis of the clamped reduced component: eigenvalues of its state-space model.

Each underdamped eigenvalue pair is lambda = -zeta omega_n +/- j omega_n sqrt(1 - zeta^2)
(eq. 9, Passigato et al. 2023, Sect. 4.2.2); omega_n = |lambda| [rad/s] and zeta =
-Re(lambda) / |lambda| [-]. Modes are labelled ('torsion', 'bending', 'in_plane') by matching
omega_n to the undamped modes of the reduced component and taking their labels.
"""
from dataclasses import dataclass

import numpy as np

from motoflex_ros.bench.response import lateral_state_space
from motoflex_ros.errors import ModelError

__all__ = ["Mode", "ModeSet", "clamped_modes"]


@dataclass(frozen=True)
class Mode:
    """One underdamped mode: eigenvalue [1/s], omega_n [rad/s], zeta [-], label."""

    eigenvalue: complex
    omega_n: float
    zeta: float
    label: str

    @property
    def f_hz(self):
        """Undamped natural frequency omega_n / (2 pi) [Hz]."""
        return self.omega_n / (2.0 * np.pi)


@dataclass(frozen=True)
class ModeSet:
    """Modes of the clamped reduced component, ascending in omega_n."""

    modes: tuple

    def first(self, label=None):
        """The lowest mode (with ``label`` if given); ModelError when there is none."""
        for mode in self.modes:
            if label is None or mode.label == label:
                return mode
        raise ModelError(f"the component has no {label or ''} mode".replace("  ", " "))

    def first_lateral(self):
        """The lowest torsion or bending mode: the first mode a lateral load excites."""
        lateral = [m for m in self.modes if m.label in ("torsion", "bending")]
        if not lateral:
            raise ModelError("the component has no torsion or bending mode")
        return lateral[0]

    def frequency(self, name):
        """Frequency [Hz] of 'first' (lowest torsion/bending), 'first torsion', 'first bending'."""
        if name == "first":
            return self.first_lateral().f_hz
        return self.first(name.split()[1]).f_hz


def clamped_modes(reduced):
    """ModeSet of a ReducedComponent from the eigenvalues of its state-space model (eq. 9).

    The eigenvalue pairs, sorted by |lambda|, are paired in order with the undamped modes of
    the reduced component (``frequencies_hz``, ascending), whose labels they take; with light
    (modal) damping the order is the same.
    """
    lam = np.linalg.eigvals(lateral_state_space(reduced).A)
    lam = lam[lam.imag > 0]
    lam = lam[np.argsort(np.abs(lam))]
    if len(lam) != len(reduced.mode_labels):
        raise ModelError(f"{reduced.name}: {len(lam)} underdamped eigenvalue pairs for "
                         f"{len(reduced.mode_labels)} modes (overdamped modes?)")
    modes = []
    for value, label in zip(lam, reduced.mode_labels):
        omega = float(abs(value))
        modes.append(Mode(complex(value), omega, float(-value.real / omega), label))
    return ModeSet(tuple(modes))
