"""Drawing geometry of identified deformation axes (shared by the report and the recording)."""
import numpy as np

from motoflex_ros.lumped_stiffness.axis import DeformationAxis, axis_in_plane

__all__ = ["axis_from_l_beta", "axis_segment_xyz"]


def axis_from_l_beta(l, beta, q0):
    """A :class:`DeformationAxis` from the identified l [m] and beta [rad] (eqs. 5-7).

    The joint lies on the line O-q0 at the signed distance l (eq. 5); b follows from eq. (7).
    """
    q0 = np.asarray(q0, float)
    length = np.hypot(q0[0], q0[2])
    return DeformationAxis(l=float(l), beta=float(beta), b=float((length - l) * np.sin(beta)),
                           x_j=float(l * q0[0] / length), z_j=float(l * q0[2] / length))


def axis_segment_xyz(l, beta, q0, half_length=None):
    """End points (2, 3) [m] of the axis drawn ``half_length`` (default |q0|) about the joint."""
    q0 = np.asarray(q0, float)
    half = half_length or float(np.hypot(q0[0], q0[2]))
    point, direction = axis_in_plane(axis_from_l_beta(l, beta, q0), q0)
    return np.array([point - half * direction, point + half * direction])
