"""Natural frequency, damping ratio, modal inertia and damping: eqs. (9)-(11), and c = gamma k.

Passigato et al. 2023, Sect. 4.2.2. The stiffness k itself is eq. (8),
:func:`motoflex_ros.lumped_stiffness.axis.axis_stiffness`.
"""
import numpy as np

__all__ = ["natural_frequency", "damping_ratio", "modal_inertia", "modal_damping",
           "static_damping", "GAMMA_S"]

GAMMA_S = 0.001  # [s] damping-to-stiffness ratio of the static lumped models (Sect. 4.2.2)


def natural_frequency(eigenvalue):
    """Eq. (9): omega_n = |lambda| [rad/s] of lambda = -zeta omega_n + j omega_n sqrt(1-zeta^2).

    Parameters
    ----------
    eigenvalue : complex
        lambda [1/s] of the mode.

    Returns
    -------
    float
        omega_n [rad/s].

    Examples
    --------
    omega_n = 10 rad/s, zeta = 0.6: lambda = -6 + 8j (sqrt(1 - 0.36) = 0.8):

    >>> natural_frequency(-6.0 + 8.0j)
    10.0

    """
    return float(abs(eigenvalue))


def damping_ratio(eigenvalue):
    """Eq. (9): zeta_n = -Re(lambda) / |lambda| [-].

    Parameters
    ----------
    eigenvalue : complex
        lambda [1/s] of the mode.

    Returns
    -------
    float
        zeta_n [-].

    Examples
    --------
    The mode of :func:`natural_frequency`'s example, omega_n = 10 rad/s and zeta = 0.6:

    >>> damping_ratio(-6.0 + 8.0j)
    0.6

    """
    return float(-np.real(eigenvalue) / abs(eigenvalue))


def modal_inertia(k, omega_n):
    """Eq. (10): J = k / omega_n^2 [kg m^2], k [N m/rad], omega_n [rad/s].

    Parameters
    ----------
    k : float
        Stiffness about the axis [N m/rad] (eq. 8).
    omega_n : float
        Natural frequency of the mode [rad/s] (eq. 9).

    Returns
    -------
    float
        J [kg m^2].

    Examples
    --------
    A 2 kg m^2 rotor on a 5000 N m/rad spring swings at sqrt(5000 / 2) = 50 rad/s:

    >>> modal_inertia(5000.0, 50.0)
    2.0

    """
    return k / omega_n**2


def modal_damping(zeta, inertia, omega_n):
    """Eq. (11): c = 2 zeta_n J omega_n [N m s/rad], J [kg m^2], omega_n [rad/s].

    Parameters
    ----------
    zeta : float
        Damping ratio zeta_n [-] (eq. 9).
    inertia : float
        Modal inertia J [kg m^2] (eq. 10).
    omega_n : float
        Natural frequency [rad/s] (eq. 9).

    Returns
    -------
    float
        c [N m s/rad].

    Examples
    --------
    The oscillator J theta'' + c theta' + k theta = 0 with J = 2 kg m^2, k = 5000 N m/rad and
    c = 20 N m s/rad has lambda^2 + 10 lambda + 2500 = 0, lambda = -5 +/- j sqrt(2475), so
    zeta = 5 / 50 = 0.1 (eq. 9); eq. (11) gives c back:

    >>> lam = complex(-5.0, np.sqrt(2475.0))
    >>> omega_n, zeta = natural_frequency(lam), damping_ratio(lam)
    >>> round(modal_damping(zeta, modal_inertia(5000.0, omega_n), omega_n), 9)
    20.0

    """
    return 2.0 * zeta * inertia * omega_n


def static_damping(k, gamma=GAMMA_S):
    """Damping c = gamma k [N m s/rad] of a static lumped model (Sect. 4.2.2, after eq. 11).

    Parameters
    ----------
    k : float
        Stiffness about the static axis [N m/rad] (eq. 8).
    gamma : float
        Damping-to-stiffness ratio [s] (the paper's 0.001 s).

    Returns
    -------
    float
        c [N m s/rad].

    Examples
    --------
    The paper's frame, k = 1.03e6 N m/rad (Table 2), gets c = 1030 N m s/rad:

    >>> round(static_damping(1.03e6), 9)
    1030.0

    """
    return gamma * k
