"""Tyre limit: the Whipple bicycle on linear tyres converges to the non-holonomic benchmark.

Cornering stiffness C grows, relaxation length 100/C shrinks, camber and aligning stiffness
are zero (holding C_gamma/C_alpha fixed would leave a steady error, docs/vehicle-engine.md). The
eigenvalues of the knife-edge model are the limit; the error falls as O(1/C).
"""
import numpy as np
import pytest
import yaml

from motoflex_ros.config import config_path
from motoflex_ros.vehicle.linearize import linearize
from motoflex_ros.vehicle.model import vehicle_from_dict


def _whipple_dict():
    with open(config_path("vehicles", "whipple_benchmark"), encoding="utf-8") as stream:
        return yaml.safe_load(stream)


def _on_tyres(cornering):
    data = _whipple_dict()
    for wheel in data["wheels"].values():
        wheel["tyre"] = {"model": "linear", "cornering_stiffness": cornering,
                         "relaxation_length": 100.0 / cornering}
    return linearize(vehicle_from_dict(data, "whipple_on_tyres"))


def _distance(eigenvalues, targets):
    return max(np.min(np.abs(eigenvalues - z)) for z in targets)


@pytest.fixture(scope="module")
def errors():
    knife = linearize(vehicle_from_dict(_whipple_dict()))
    out = {}
    for speed in (5.0, 10.0):
        targets = knife.eigenvalues(speed)
        out[speed] = [_distance(_on_tyres(c).eigenvalues(speed), targets)
                      for c in (1e6, 1e8, 1e10)]
    return out


@pytest.mark.parametrize("speed", [5.0, 10.0])
def test_tyre_limit_converges(errors, speed):
    e6, e8, e10 = errors[speed]
    # first-order convergence in 1/C: each factor 100 in C divides the error by about 100
    assert 50.0 < e6 / e8 < 200.0
    assert 50.0 < e8 / e10 < 200.0
    assert e10 < 1e-5


def test_tyre_model_adds_lateral_and_relaxation_states():
    lin = _on_tyres(1e5)
    assert lin.state_names == ("roll", "steer", "y_rate", "yaw_rate", "roll_rate", "steer_rate",
                               "rear_side_force", "rear_aligning_moment", "front_side_force",
                               "front_aligning_moment")
