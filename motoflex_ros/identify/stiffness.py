"""Natural frequency, damping ratio, modal inertia and damping: eqs. (9)-(11), and c = gamma k.

Passigato et al. 2023, Sect. 4.2.2. The stiffness k itself is eq. (8),
:func:`motoflex_ros.lumped_stiffness.axis.axis_stiffness`.
"""
import numpy as np

__all__ = ["natural_frequency", "damping_ratio", "modal_inertia", "modal_damping",
           "static_damping", "GAMMA_S"]

GAMMA_S = 0.001  # [s] damping-to-stiffness ratio of the static lumped models (Sect. 4.2.2)


def natural_frequency(eigenvalue):
    """Eq. (9): omega_n = |lambda| [rad/s] of lambda = -zeta omega_n + j omega_n sqrt(1-zeta^2)."""
    return float(abs(eigenvalue))


def damping_ratio(eigenvalue):
    """Eq. (9): zeta_n = -Re(lambda) / |lambda| [-]."""
    return float(-np.real(eigenvalue) / abs(eigenvalue))


def modal_inertia(k, omega_n):
    """Eq. (10): J = k / omega_n^2 [kg m^2], k [N m/rad], omega_n [rad/s]."""
    return k / omega_n**2


def modal_damping(zeta, inertia, omega_n):
    """Eq. (11): c = 2 zeta_n J omega_n [N m s/rad], J [kg m^2], omega_n [rad/s]."""
    return 2.0 * zeta * inertia * omega_n


def static_damping(k, gamma=GAMMA_S):
    """Damping c = gamma k [N m s/rad] of a static lumped model, gamma [s] (default 0.001 s)."""
    return gamma * k
