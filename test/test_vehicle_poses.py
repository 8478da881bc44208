"""World-frame poses along a response (motoflex_ros.vehicle.poses) against closed forms.

- Knife-edge bicycle (Whipple benchmark), constant steer delta, upright: the rolling
  constraints give the yaw rate r = -v delta cos(lambda) / w (REP-103: the benchmark's positive
  steer turns right), so the rear contact runs on a circle of radius w / (delta cos lambda)
  (small angles; the exact ground-plane steer angle differs by O(delta^2)).
- Tyred motorcycle, yaw rate and lateral velocity given as states: the heading is the exact
  integral of a constant yaw rate, the path a circle of radius v / r; a constant lateral
  velocity gives a straight line (X, Y) = (v t, v_y t).
"""
import numpy as np
import pytest

from motoflex_ros.config import config_path
from motoflex_ros.vehicle.linearize import linearize
from motoflex_ros.vehicle.model import load_vehicle
from motoflex_ros.vehicle.poses import base_rates, planar_path, world_poses

WHEELBASE, TILT = 1.02, np.pi / 10      # Meijaard et al. 2007, Table 1


@pytest.fixture(scope="module")
def whipple():
    return linearize(load_vehicle(config_path("vehicles", "whipple_benchmark")))


@pytest.fixture(scope="module")
def touring():
    return linearize(load_vehicle(config_path("vehicles", "touring")))


def constant_states(lin, time, **values):
    states = np.zeros((len(time), len(lin.state_names)))
    for name, value in values.items():
        states[:, lin.state_names.index(name)] = value
    return states


def test_knife_edge_constant_steer_circle_analytic(whipple):
    speed, delta = 5.0, 0.01
    time = np.linspace(0.0, 10.0, 201)
    poses = world_poses(whipple, time, constant_states(whipple, time, steer=delta), speed)
    radius = WHEELBASE / (delta * np.cos(TILT))
    np.testing.assert_allclose(poses.heading, -speed * time / radius, rtol=1e-3, atol=1e-12)
    distance = np.linalg.norm(poses.position - [0.0, -radius], axis=1)
    np.testing.assert_allclose(distance, radius, rtol=1e-4)
    assert poses.position[-1, 1] < -10.0          # the path turned right, visibly
    # the rigid bicycle moves as a whole: distances between its frames stay as at t = 0
    gaps = np.linalg.norm(poses.translations - poses.translations[:, :1], axis=2)
    np.testing.assert_allclose(gaps, gaps[:1].repeat(len(time), 0), atol=1e-9)


def test_knife_edge_yaw_rate_has_the_steer_rate_term_analytic(whipple):
    """Yaw rate r = (v delta + c delta') cos(lambda) / w (benchmark kinematics), c = 0.08 m."""
    speed, rate = 5.0, 0.2
    states = constant_states(whipple, [0.0], steer_rate=rate)
    _, yaw_rate = base_rates(whipple.system, states, speed)
    assert yaw_rate[0] == pytest.approx(-0.08 * rate * np.cos(TILT) / WHEELBASE, rel=1e-9)


def test_yaw_rate_input_integrated_exactly_analytic(touring):
    speed, yaw_rate = 20.0, 0.5
    time = np.linspace(0.0, 6.0, 601)
    poses = world_poses(touring, time, constant_states(touring, time, yaw_rate=yaw_rate),
                        speed)
    np.testing.assert_allclose(poses.heading, yaw_rate * time, rtol=1e-12, atol=1e-14)
    radius = speed / yaw_rate
    distance = np.linalg.norm(poses.position - [0.0, radius], axis=1)
    # trapezoidal rule: error below T v r^2 dt^2 / 12 = 5e-4 m here
    np.testing.assert_allclose(distance, radius, atol=5e-4)
    assert poses.heading[-1] == pytest.approx(3.0)   # more than a right angle: world frame


def test_lateral_velocity_gives_a_straight_line_analytic():
    time = np.linspace(0.0, 2.0, 11)
    heading, position = planar_path(time, 10.0, np.full(11, 0.3), np.zeros(11))
    np.testing.assert_allclose(heading, 0.0)
    np.testing.assert_allclose(position, np.column_stack([10.0 * time, 0.3 * time]),
                               rtol=1e-12)
