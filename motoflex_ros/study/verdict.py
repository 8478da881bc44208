"""The stability verdict of a speed sweep: each tracked mode's least-damped point.

Passigato et al. 2023, Sect. 4.3: a mode is stable at a speed where the real part of its
eigenvalue is negative; eq. (13)'s s1 is the largest real part over a range. The verdict a
report and the console print is that s1 over the whole sweep, where it happens, the mode's
frequency there, and whether the mode is stable at every speed of the sweep.
"""
from dataclasses import dataclass

import numpy as np

from motoflex_ros.vehicle.mode_names import STUDIED_MODES

__all__ = ["ModeVerdict", "mode_verdict", "stability_verdict"]


@dataclass(frozen=True)
class ModeVerdict:
    """The least-damped point of one tracked mode over a sweep.

    ``real`` [1/s] the largest real part (eq. 13's s1 over the sweep), at ``speed_kmh``
    [km/h] with the frequency ``frequency_hz`` [Hz] there; ``stable`` True when the real part
    is negative at every speed where the mode was found; ``unstable_kmh`` the speeds [km/h]
    where it is not; ``found`` how many of the sweep's speeds have the mode.
    """

    mode: str
    real: float
    speed_kmh: float
    frequency_hz: float
    stable: bool
    unstable_kmh: tuple
    found: int
    index: int

    def as_dict(self):
        """Plain JSON-able dict (the campaign's --json ``stability`` entries)."""
        return {"least_damped_real": self.real, "least_damped_speed_kmh": self.speed_kmh,
                "frequency_hz": self.frequency_hz, "stable": self.stable,
                "unstable_speeds_kmh": list(self.unstable_kmh), "speeds_found": self.found}


def mode_verdict(mode, speeds_kmh, eigenvalues):
    """The :class:`ModeVerdict` of one mode (eq. 13 over the whole sweep).

    Parameters
    ----------
    mode : str
        The mode's name (weave, wobble).
    speeds_kmh : array (n,)
        Speeds of the sweep [km/h].
    eigenvalues : array (n,) complex
        The mode's eigenvalue at each speed [1/s]; NaN where the mode was not found.

    Returns
    -------
    ModeVerdict or None
        None when the mode was found at no speed.

    Examples
    --------
    >>> v = mode_verdict("wobble", [40, 100, 200], [-3 + 50j, -0.5 + 55j, 0.2 + 52j])
    >>> (v.real, v.speed_kmh, v.stable, v.unstable_kmh)
    (0.2, 200.0, False, (200.0,))
    >>> round(v.frequency_hz, 3)
    8.276

    """
    speeds = np.asarray(speeds_kmh, float)
    lam = np.asarray(eigenvalues, complex)
    found = np.isfinite(lam.real) & np.isfinite(lam.imag)
    if not found.any():
        return None
    i = int(np.argmax(np.where(found, lam.real, -np.inf)))
    unstable = tuple(float(v) for v in speeds[found & (lam.real >= 0.0)])
    return ModeVerdict(mode, float(lam[i].real), float(speeds[i]),
                       float(abs(lam[i].imag) / (2 * np.pi)), not unstable, unstable,
                       int(found.sum()), i)


def stability_verdict(speeds_kmh, modes, names=STUDIED_MODES):
    """{mode: :class:`ModeVerdict`} of the ``names`` present in ``modes`` ({mode: eigenvalue
    per speed, complex [1/s]}), over ``speeds_kmh`` [km/h]; modes never found are left out.

    >>> verdict = stability_verdict([40, 210], {"weave": [-2 + 20j, -1 + 25j]})
    >>> verdict["weave"].stable, list(verdict)
    (True, ['weave'])
    """
    out = {}
    for name in names:
        if name in modes:
            verdict = mode_verdict(name, speeds_kmh, modes[name])
            if verdict is not None:
                out[name] = verdict
    return out
