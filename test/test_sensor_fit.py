"""Marker sensor: rigid fit round trips, rotation maps, seeded noise, resolution and latency."""
import numpy as np
import pytest

from motoflex_ros.bench.sensor import (
    DEFAULT_MARKERS,
    MarkerSensor,
    SensorSettings,
    fit_pose,
    marker_positions,
)
from motoflex_ros.spatial import rotation_from_vector, rotation_vector

Q0 = np.array([0.62, 0.0, 0.42])


def random_rotation_vector(rng, size):
    """A rotation vector of angle size * U(0.1, 1) (< pi, where the vector is unique)."""
    axis = rng.normal(size=3)
    return axis / np.linalg.norm(axis) * size * rng.uniform(0.1, 1.0)


def random_pose(rng, size):
    return rng.normal(scale=1e-3, size=3), random_rotation_vector(rng, size)


@pytest.mark.parametrize("size", [1e-7, 1e-3, 0.3, 3.1])
def test_rotation_vector_roundtrip(size):
    rng = np.random.default_rng(1)
    for _ in range(20):
        theta = random_rotation_vector(rng, size)
        rot = rotation_from_vector(theta)
        assert np.allclose(rot @ rot.T, np.eye(3), atol=1e-14)
        assert np.allclose(rotation_vector(rot), theta, rtol=1e-12, atol=1e-20)


def test_rotation_from_vector_matches_expm_analytic():
    from scipy.linalg import expm
    theta = np.array([0.3, -0.2, 0.5])
    skew = np.array([[0, -theta[2], theta[1]], [theta[2], 0, -theta[0]],
                     [-theta[1], theta[0], 0]])
    assert np.allclose(rotation_from_vector(theta), expm(skew), atol=1e-14)


@pytest.mark.parametrize("size", [1e-4, 1e-2, 3.0])
def test_kabsch_recovers_exact_pose_roundtrip(size):
    rng = np.random.default_rng(2)
    reference = Q0 + np.asarray(DEFAULT_MARKERS)
    for _ in range(10):
        u, theta = random_pose(rng, size)
        rot = rotation_from_vector(theta)
        measured = marker_positions(Q0 + u, rot, Q0, DEFAULT_MARKERS)
        position, rotation = fit_pose(measured, reference, Q0)
        assert np.allclose(position, Q0 + u, atol=1e-15)
        assert np.allclose(rotation_vector(rotation), theta, rtol=1e-9, atol=1e-15)


def test_kabsch_least_squares_beats_perturbed_pose():
    """With noisy markers the fit minimises the residual: any nearby pose does worse."""
    rng = np.random.default_rng(3)
    reference = Q0 + np.asarray(DEFAULT_MARKERS)
    measured = reference + rng.normal(scale=1e-4, size=reference.shape)
    position, rotation = fit_pose(measured, reference, Q0)

    def residual(q, r):
        return np.sum((marker_positions(q, r, Q0, DEFAULT_MARKERS) - measured) ** 2)

    best = residual(position, rotation)
    for _ in range(50):
        dq, dt = rng.normal(scale=1e-6, size=3), rng.normal(scale=1e-5, size=3)
        assert residual(position + dq, rotation_from_vector(dt) @ rotation) >= best


def test_sensor_noise_is_seeded_and_ordered():
    settings = SensorSettings(latency_s=0.0)
    a, b = MarkerSensor(settings, Q0, seed=7), MarkerSensor(settings, Q0, seed=7)
    c = MarkerSensor(settings, Q0, seed=8)
    rot = rotation_from_vector([1e-3, 2e-3, 0.0])
    ma = [a.capture(i, 0.001 * i, Q0, rot)[0] for i in range(5)]
    mb = [b.capture(i, 0.001 * i, Q0, rot)[0] for i in range(5)]
    mc = [c.capture(i, 0.001 * i, Q0, rot)[0] for i in range(5)]
    assert all(np.array_equal(x.markers, y.markers) for x, y in zip(ma, mb))
    assert not np.array_equal(ma[0].markers, mc[0].markers)


def test_sensor_noise_level_and_resolution():
    settings = SensorSettings(noise_m=5e-6, resolution_m=1e-6, latency_s=0.0)
    sensor = MarkerSensor(settings, Q0, seed=1)
    errors = []
    for i in range(2000):
        m = sensor.capture(i, 1e-3 * i, Q0, np.eye(3))[0]
        assert np.allclose(m.markers / 1e-6, np.round(m.markers / 1e-6), atol=1e-6)
        errors.append(m.markers - sensor.reference)
    std = np.std(np.array(errors))
    # noise 5e-6 plus uniform rounding error of variance res^2 / 12
    assert std == pytest.approx(np.sqrt(5e-6**2 + 1e-12 / 12), rel=0.03)


def test_sensor_latency_delays_delivery():
    settings = SensorSettings(noise_m=0.0, resolution_m=0.0, latency_s=0.0025)
    sensor = MarkerSensor(settings, Q0, seed=0)
    delivered = [[m.index for m in sensor.capture(i, 1e-3 * i, Q0, np.eye(3))]
                 for i in range(6)]
    assert delivered == [[], [], [], [0], [1], [2]]
    assert [m.index for m in sensor.flush()] == [3, 4, 5]


def test_capture_from_true_markers_is_bit_identical_roundtrip():
    """A ROS node that receives the simulator's true markers gets exactly the offline result."""
    settings = SensorSettings(latency_s=0.0)
    by_pose, by_markers = MarkerSensor(settings, Q0, seed=4), MarkerSensor(settings, Q0, seed=4)
    rng = np.random.default_rng(5)
    for i in range(20):
        u, theta = random_pose(rng, 1e-3)
        rot = rotation_from_vector(theta)
        a = by_pose.capture(i, 1e-3 * i, Q0 + u, rot)[0]
        b = by_markers.capture_markers(i, 1e-3 * i,
                                       marker_positions(Q0 + u, rot, Q0, DEFAULT_MARKERS))[0]
        assert np.array_equal(a.markers, b.markers)
        assert np.array_equal(a.pose_vector(Q0), b.pose_vector(Q0))
