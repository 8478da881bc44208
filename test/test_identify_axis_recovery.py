"""Exact recovery: a small rigid rotation about a known axis in the x-z plane, measured by the
markers and fitted (Kabsch), gives back that axis's l, beta, b through eqs. (1)-(7)."""
import itertools

import numpy as np
import pytest

from motoflex_ros.bench.sensor import (
    DEFAULT_MARKERS,
    MarkerSensor,
    SensorSettings,
    marker_positions,
)
from motoflex_ros.lumped_stiffness.axis import deformation_axis
from motoflex_ros.spatial import rotation_from_vector

EXACT = SensorSettings(noise_m=0.0, resolution_m=0.0, latency_s=0.0)
Q0S = [(0.6, 0.3), (-0.6, 0.3), (-0.5, -0.4), (0.4, -0.7), (0.0, 0.5), (0.7, 0.0)]
BETAS = [1e-3, 0.01, 0.7, 1.4, np.pi / 2, 1.9, 2.6, np.pi - 0.01, np.pi - 1e-3]
JOINTS = [0.2, -0.3]
ANGLES = [1e-3, -2e-4]


def rigid_rotation(q0, l, beta, angle):
    """Pose of the loaded end after a rotation ``angle`` about the axis (l, beta)."""
    length = np.hypot(q0[0], q0[2])
    theta = np.arctan2(q0[2], q0[0]) + beta
    joint = l * np.array([q0[0], 0.0, q0[2]]) / length
    rot = rotation_from_vector(angle * np.array([np.cos(theta), 0.0, np.sin(theta)]))
    return joint + rot @ (q0 - joint), rot


@pytest.mark.parametrize("xz, beta, l, angle",
                         list(itertools.product(Q0S, BETAS, JOINTS, ANGLES)))
def test_rigid_rotation_axis_recovered_exactly(xz, beta, l, angle):
    q0 = np.array([xz[0], 0.0, xz[1]])
    q, rot = rigid_rotation(q0, l, beta, angle)
    sensor = MarkerSensor(EXACT, q0, seed=0)
    measured = sensor.capture(0, 0.0, q, rot)[0]
    axis = deformation_axis(measured.position, measured.rotation, q0)
    length = np.hypot(q0[0], q0[2])
    # rounding error of l: about eps / (|angle| sin(beta)) (axis nearly parallel to O-q0)
    tol = max(1e-9, 10 * np.finfo(float).eps / (abs(angle) * np.sin(beta)))
    assert axis.l == pytest.approx(l, abs=tol)
    assert np.angle(np.exp(2j * (axis.beta - beta))) / 2 == pytest.approx(0.0, abs=1e-9)
    assert 0.0 <= axis.beta < np.pi
    assert axis.b == pytest.approx((length - l) * np.sin(beta), abs=1e-9)


def test_marker_positions_of_rigid_rotation_keep_distances_roundtrip():
    q0 = np.array([0.6, 0.0, 0.3])
    q, rot = rigid_rotation(q0, 0.2, 1.0, 1e-2)
    moved = marker_positions(q, rot, q0, DEFAULT_MARKERS)
    ref = q0 + np.asarray(DEFAULT_MARKERS)
    for i, j in itertools.combinations(range(len(ref)), 2):
        assert np.linalg.norm(moved[i] - moved[j]) == pytest.approx(
            np.linalg.norm(ref[i] - ref[j]), abs=1e-15)


def test_running_mean_across_beta_wrap_analytic():
    """Peaks on both sides of beta = 0 (one reported near pi): the mean axis is the mean of
    the unwrapped angles, and b = (L - l) sin(beta) follows the unwrapping (eq. 7)."""
    from motoflex_ros.identify.peaks import RunningMean, wrap_axis
    length, l = 0.8, 0.3
    mean = RunningMean(length, 1e-3, 1e-3, 2)
    for beta in (0.0015, -0.0005):
        wrapped, b = wrap_axis(beta, (length - l) * np.sin(beta))
        assert 0.0 <= wrapped < np.pi and b >= 0.0      # as eqs. (6)-(7) report them
        mean.add(l, wrapped, b)
    beta_mean, b_mean = mean.means[-1]
    assert beta_mean == pytest.approx(0.0005, abs=1e-15)
    assert b_mean == pytest.approx((length - l) * (np.sin(0.0015) + np.sin(-0.0005)) / 2,
                                   rel=1e-12)


@pytest.mark.parametrize("offset", [0.0, 0.05, -0.03])
@pytest.mark.parametrize("xz", Q0S)
def test_axis_parallel_to_line_has_no_joint_and_its_distance_as_arm(xz, offset):
    """An axis parallel to O-q0 (a straight tube twisting about itself: offset 0) meets the
    line nowhere, so l is undefined (NaN) whatever the round-off; b is the distance of q0 from
    the axis, the limit of eq. (7) (L - l) sin(beta) as beta -> 0. Decided by a tolerance: the
    outcome must not depend on the BLAS kernel."""
    q0 = np.array([xz[0], 0.0, xz[1]])
    e0 = q0 / np.linalg.norm(q0)
    normal = np.cross(e0, [0.0, 1.0, 0.0])            # in the x-z plane, across O-q0
    joint = offset * normal
    rot = rotation_from_vector(1e-3 * e0)
    q = joint + rot @ (q0 - joint)
    for wobble in (0.0, 1e-19, -3e-18):               # round-off in the fitted rotation
        tilted = rot + wobble * np.outer(normal, [0.0, 1.0, 0.0])
        axis = deformation_axis(q, tilted, q0)
        assert np.isnan(axis.l) and np.isnan(axis.x_j)
        assert min(axis.beta, np.pi - axis.beta) < 1e-12
        assert axis.b == pytest.approx(abs(offset), abs=1e-12)


def test_axis_tilted_a_micro_radian_still_has_its_joint():
    """Only an axis parallel to within PARALLEL_TOL counts as parallel: one tilted by 1e-6 rad
    gives its l, beta, b back (eqs. 3-7)."""
    q0 = np.array([0.6, 0.0, 0.3])
    q, rot = rigid_rotation(q0, 0.2, 1e-6, 1e-3)
    axis = deformation_axis(q, rot, q0)
    assert axis.l == pytest.approx(0.2, rel=1e-6)
    assert axis.beta == pytest.approx(1e-6, rel=1e-6)
