"""Kinematics of the vehicle engine: velocities and bias accelerations against finite
differences of positions (docs/vehicle-engine.md, the order of the checks), and the toroidal
contact point of a leaned wheel against its closed form."""
import numpy as np
import pytest
import yaml

from motoflex_ros.config import config_path
from motoflex_ros.vehicle.contact import contact_state
from motoflex_ros.vehicle.kinematics import compile_tree, frame_states
from motoflex_ros.vehicle.model import vehicle_from_dict

H = 1e-6


@pytest.fixture(scope="module")
def crowned():
    with open(config_path("vehicles", "whipple_benchmark"), encoding="utf-8") as stream:
        data = yaml.safe_load(stream)
    data["wheels"]["rear"]["crown_radius"] = 0.08
    data["wheels"]["front"]["crown_radius"] = 0.05
    model = vehicle_from_dict(data, "crowned_whipple")
    tree = compile_tree(model)
    rng = np.random.default_rng(7)
    q = rng.uniform(-0.3, 0.3, len(tree.coordinates))
    q[:2] = 0.0   # heading quasi-coordinates x, y are cyclic: positions held at zero
    u = rng.uniform(-2.0, 2.0, len(tree.coordinates))
    return model, tree, q, u


def _positions(tree, q, u, point):
    return [f.R @ point + f.t for f in frame_states(tree, q, u)[1:]]


def test_velocity_matches_position_differences(crowned):
    _, tree, q, u = crowned
    point = np.array([0.3, -0.2, 0.5])
    plus, minus = _positions(tree, q + H * u, u, point), _positions(tree, q - H * u, u, point)
    for frame, xp, xm in zip(frame_states(tree, q, u)[1:], plus, minus):
        x = frame.R @ point + frame.t
        np.testing.assert_allclose(frame.v0 + np.cross(frame.w, x), (xp - xm) / (2 * H),
                                   atol=1e-8)


def test_bias_matches_twist_differences(crowned):
    _, tree, q, u = crowned
    plus, minus = frame_states(tree, q + H * u, u), frame_states(tree, q - H * u, u)
    for frame, fp, fm in zip(frame_states(tree, q, u)[1:], plus[1:], minus[1:]):
        np.testing.assert_allclose(frame.dw, (fp.w - fm.w) / (2 * H), atol=1e-7)
        np.testing.assert_allclose(frame.dv0, (fp.v0 - fm.v0) / (2 * H), atol=1e-7)


@pytest.mark.parametrize("direction", ["long", "lat", "normal"])
def test_contact_bias_matches_differences(crowned, direction):
    """d/dt of the contact-point constraint row, with the contact point moving on the tyre."""
    model, tree, q, u = crowned

    def row_value(qq):
        frames = frame_states(tree, qq, u)
        values = []
        for wheel, f in zip(model.wheels, tree.wheel_frames):
            row, bias = contact_state(wheel, frames[f], u).row(direction)
            values.append((row @ u, bias))
        return values

    plus, minus, here = row_value(q + H * u), row_value(q - H * u), row_value(q)
    for (vp, _), (vm, _), (_, bias) in zip(plus, minus, here):
        assert bias == pytest.approx((vp - vm) / (2 * H), abs=1e-7)


@pytest.mark.parametrize("lean", [0.0, 0.3, -0.6])
def test_toroidal_contact_point_analytic(crowned, lean):
    """Wheel leaned by roll phi: P = c + (r - r_c)(0, sin phi, -cos phi) + r_c (0, 0, -1)."""
    model, tree, _, _ = crowned
    q = np.zeros(len(tree.coordinates))
    q[tree.index("roll")] = lean
    frames = frame_states(tree, q, q)
    for wheel, f in zip(model.wheels, tree.wheel_frames):
        frame = frames[f]
        centre = frame.R @ wheel.centre + frame.t
        state = contact_state(wheel, frame, q)
        r, rc = wheel.radius, wheel.crown_radius
        want = centre + (r - rc) * np.array([0.0, np.sin(lean), -np.cos(lean)])
        want += rc * np.array([0.0, 0.0, -1.0])
        np.testing.assert_allclose(state.P, want, atol=1e-14)
        assert state.camber == pytest.approx(-lean, abs=1e-14)
