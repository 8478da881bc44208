"""Displacement peaks of a harmonic test and the running mean of l, beta, b (Sect. 4.2.1).

Peak estimation. At high excitation frequency (the swingarm's torsion) a sensor frame rarely
falls on a peak: with 8 samples per period the largest raw sample misses the peak by up to
1 - cos(pi/8) = 7.6 % in amplitude and by up to 1/16 period in time, and the pose channels peak
at the same instant only in steady state. Instead, over each whole period of the known
excitation frequency f, every pose channel (q - q0, rotation vector) is fitted by least squares
with p(t) = c + a cos(w t) + s sin(w t), w = 2 pi f. The lateral channel y_q of the fit has its
maxima at w t = atan2(s_y, a_y) and its minima half a period later; all six channels of the fit
are evaluated there, giving two peak poses per period. For a steady sinusoid sampled at >= 4
samples per period the fit is exact whatever the phase of the samples; with noise it uses every
sample of the period (variance reduced by about 2/n), and noise-free transients at other
frequencies are partly rejected. Raw-sample picking or parabolic interpolation would need the
peak of every channel at the same sample and is biased by the sampling phase.
"""
from dataclasses import dataclass

import numpy as np

from motoflex_ros.lumped_stiffness.axis import deformation_axis
from motoflex_ros.spatial import rotation_from_vector

__all__ = ["fit_sine", "peak_poses", "axis_of_pose", "RunningMean", "unwrap_angle",
           "unwrap_axis", "wrap_axis", "joint_distance_from_arm"]

LATERAL = 1  # y_q channel of a pose vector (q - q0, theta)


def fit_sine(tau, poses, omega):
    """Least-squares fit p = c + a cos(omega tau) + s sin(omega tau) per channel.

    tau (n,) [s], poses (n, 6) [m, rad], omega [rad/s]; returns (c, a, s), each (6,).
    """
    design = np.column_stack([np.ones_like(tau), np.cos(omega * tau), np.sin(omega * tau)])
    coef, *_ = np.linalg.lstsq(design, poses, rcond=None)
    return coef[0], coef[1], coef[2]


def peak_poses(c, a, s):
    """Poses (2, 6) at the maximum and the minimum of the fitted lateral channel y_q."""
    phase = np.arctan2(s[LATERAL], a[LATERAL])
    swing = a * np.cos(phase) + s * np.sin(phase)
    return np.array([c + swing, c - swing])


def axis_of_pose(pose, q0):
    """Deformation axis (eqs. 1-7) of a pose vector (q - q0, rotation vector) [m, rad]."""
    q0 = np.asarray(q0, float)
    return deformation_axis(q0 + pose[:3], rotation_from_vector(pose[3:]), q0)


def unwrap_angle(beta, reference):
    """Angle beta [rad] shifted by a multiple of pi into (reference - pi/2, reference + pi/2]."""
    return reference + np.mod(beta - reference + np.pi / 2, np.pi) - np.pi / 2


def unwrap_axis(beta, b, reference):
    """(beta, b) with beta unwrapped as in :func:`unwrap_angle`; b = (L - l) sin(beta) changes
    sign with every pi added to beta, so that eq. (7) still holds."""
    unwrapped = unwrap_angle(beta, reference)
    turns = int(round((unwrapped - beta) / np.pi))
    return unwrapped, b * (-1.0) ** turns


def wrap_axis(beta, b):
    """(beta, b) with beta wrapped into [0, pi) and b following it (eq. 7).

    Parameters
    ----------
    beta : float
        Axis angle to O-q0 [rad], any value.
    b : float
        Moment arm [m] that goes with it, b = (L - l) sin(beta).

    Returns
    -------
    (float, float)
        beta [rad] in [0, pi) and b [m]: the same axis line.

    Examples
    --------
    Turning the axis by pi flips the sign of sin(beta), so of b:

    >>> beta, b = wrap_axis(np.pi + 0.5, 0.2)
    >>> round(beta, 12), b
    (0.5, -0.2)

    """
    wrapped = float(np.mod(beta, np.pi))
    return wrapped, b * (-1.0) ** int(round((wrapped - beta) / np.pi))


def joint_distance_from_arm(beta, b, length):
    """Joint distance l = L - b / sin(beta) [m]: eq. (7) solved for l.

    Parameters
    ----------
    beta : float
        Axis angle to O-q0 [rad] (eq. 6).
    b : float
        Moment arm [m] (eq. 7).
    length : float
        L = |O-q0| [m].

    Returns
    -------
    float
        l [m].

    Examples
    --------
    L = 1 m, an axis at 30 deg with the arm 0.3 m meets O-q0 at 0.4 m (0.6 sin 30 deg = 0.3):

    >>> round(float(joint_distance_from_arm(np.pi / 6, 0.3, 1.0)), 12)
    0.4

    """
    return length - b / np.sin(beta)


@dataclass
class RunningMean:
    """Running mean over peaks and the settling test of Sect. 4.2.1.

    The axis of each peak is averaged through its angle beta and arm b (the signed distance
    of q0 from the axis, eq. 7), which fix the axis line in the x-z plane; the mean joint
    distance follows as l = L - b / sin(beta). This is the same axis as averaging l directly
    when the peaks agree, and stays well-conditioned for axes nearly parallel to O-q0 (beta
    near 0 or pi), where l of a single peak is very sensitive to noise. beta is unwrapped
    against the first peak so that values near 0 and near pi average correctly. Settled when
    the running means of beta and b have stayed within the tolerance bands (band_angle_rad,
    band_length_m) over the last ``settle_peaks`` peaks.
    """

    length: float
    band_length_m: float
    band_angle_rad: float
    settle_peaks: int

    def __post_init__(self):
        self.values = []
        self.means = []

    def add(self, l, beta, b):
        """Add one peak's (l [m], beta [rad], b [m])."""
        if self.values:
            beta, b = unwrap_axis(beta, b, self.values[0][1])
        self.values.append((l, beta, b))
        self.means.append(np.mean(np.array(self.values)[:, 1:], axis=0))

    @property
    def settled(self):
        """True once the running mean stays inside the bands for ``settle_peaks`` peaks."""
        if len(self.means) < self.settle_peaks:
            return False
        recent = np.array(self.means[-self.settle_peaks:])
        spread = recent.max(axis=0) - recent.min(axis=0)
        return bool(spread[0] <= self.band_angle_rad and spread[1] <= self.band_length_m)
