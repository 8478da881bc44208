"""Massless bodies and force elements in the one engine (descriptor form E x' = A x).

- A massless body between fork and front wheel on a stiff revolute spring: the Whipple
  eigenvalues come back as the stiffness grows (first-order convergence in 1/k).
- A massless body on a spring k and damper c that carries nothing: E is singular, the
  generalized eigenproblem drops the infinite eigenvalues and finds -k/c (analytic) besides the
  unchanged Whipple eigenvalues.
- A force element acting on the steer coordinate equals the same joint spring (round trip).
"""
import copy
from dataclasses import replace

import numpy as np
import pytest
import yaml

from motoflex_ros.config import config_path
from motoflex_ros.vehicle.linearize import linearize
from motoflex_ros.vehicle.model import vehicle_from_dict

MASSLESS = {"mass": 0.0, "com": [1.0, 0.0, 0.6]}


@pytest.fixture(scope="module")
def whipple():
    with open(config_path("vehicles", "whipple_benchmark"), encoding="utf-8") as stream:
        return yaml.safe_load(stream)


@pytest.fixture(scope="module")
def rigid(whipple):
    return linearize(vehicle_from_dict(whipple))


def _distance(got, want):
    return max(np.min(np.abs(got - z)) for z in want)


def _fork_flex(whipple, stiffness):
    data = copy.deepcopy(whipple)
    data["bodies"]["fork_flex"] = MASSLESS
    data["joints"]["fork_bending"] = {"type": "revolute", "parent": "front_frame",
                                      "child": "fork_flex", "axis": [1.0, 0.0, 0.0],
                                      "point": [1.0, 0.0, 0.75], "stiffness": stiffness}
    data["wheels"]["front"]["carrier"] = "fork_flex"
    return linearize(vehicle_from_dict(data, "fork_flex"))


def test_massless_flex_converges_to_rigid(whipple, rigid):
    errors = [_distance(_fork_flex(whipple, k).eigenvalues(5.0), rigid.eigenvalues(5.0))
              for k in (1e5, 1e7, 1e9)]
    assert 50.0 < errors[0] / errors[1] < 200.0
    assert 50.0 < errors[1] / errors[2] < 200.0
    assert errors[2] < 1e-5


def test_singular_descriptor_analytic(whipple, rigid):
    data = copy.deepcopy(whipple)
    data["bodies"]["dangling"] = MASSLESS
    k, c = 300.0, 20.0
    data["joints"]["dangling_hinge"] = {"type": "revolute", "parent": "rear_frame",
                                        "child": "dangling", "axis": [0.0, 1.0, 0.0],
                                        "point": [0.5, 0.0, 0.6], "stiffness": k, "damping": c}
    lin = linearize(vehicle_from_dict(data, "dangling"))
    E, _ = lin.pencil([5.0])
    assert np.linalg.matrix_rank(E[0]) == E.shape[-1] - 1
    got = lin.eigenvalues(5.0)
    want = np.append(rigid.eigenvalues(5.0), -k / c)
    assert len(got) == len(want)
    assert _distance(got, want) < 1e-9


class SteerSpring:
    """A force element: torque -k delta on the steer coordinate."""

    def __init__(self, stiffness):
        self.stiffness = stiffness

    def generalized_residual(self, system, frames, q, u, udot):
        out = np.zeros(len(q), q.dtype)
        out[system.tree.index("steer")] = self.stiffness * q[system.tree.index("steer")]
        return out


def test_force_element_equals_joint_spring_roundtrip(whipple):
    model = vehicle_from_dict(whipple)
    with_element = linearize(replace(model, elements=(SteerSpring(40.0),)))
    data = copy.deepcopy(whipple)
    data["joints"]["steer"]["stiffness"] = 40.0
    with_joint = linearize(vehicle_from_dict(data))
    np.testing.assert_allclose(with_element.A_coeffs, with_joint.A_coeffs, atol=1e-10)
    np.testing.assert_allclose(with_element.E_coeffs, with_joint.E_coeffs, atol=1e-10)


def test_pulse_response_with_singular_descriptor_roundtrip(whipple, rigid):
    """A massless body that carries nothing changes nothing: the steer-pulse response of the
    bicycle with it (singular E, reduced to its regular part) equals the rigid one."""
    from motoflex_ros.vehicle.steer_pulse import steer_pulse_response

    data = copy.deepcopy(whipple)
    data["bodies"]["dangling"] = MASSLESS
    data["joints"]["dangling_hinge"] = {"type": "revolute", "parent": "rear_frame",
                                        "child": "dangling", "axis": [0.0, 1.0, 0.0],
                                        "point": [0.5, 0.0, 0.6], "stiffness": 300.0,
                                        "damping": 20.0}
    singular = linearize(vehicle_from_dict(data, "dangling"))
    names = ("steer", "roll", "roll_rate", "steer_rate")
    want = steer_pulse_response(rigid, 5.0, torque=1.0, t_end=2.0, outputs=names).outputs
    got = steer_pulse_response(singular, 5.0, torque=1.0, t_end=2.0, outputs=names).outputs
    np.testing.assert_allclose(got, want, atol=1e-10 * np.abs(want).max())
