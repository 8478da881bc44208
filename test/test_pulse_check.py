"""Issue 22 (2): the linearized eigenvalues checked in the time domain. The touring
motorcycle's NONLINEAR equations are integrated after the review's small steer pulse (20 N m x
0.05 s) at 100 km/h; weave and wobble read back by the matrix pencil must lie within 1 % of the
eigenvalues (frequency and real part), and the nonlinear response within 1 % of the exact
discretisation of the linear one. One nonlinear run: about 6 s of CPU (more wall time on a
loaded machine)."""
import numpy as np
import pytest
import yaml

from motoflex_ros.cli.eig import pulse_check_to_json
from motoflex_ros.config import config_path
from motoflex_ros.errors import ModelError
from motoflex_ros.study.pulse_check import pulse_check
from motoflex_ros.units import kmh_to_ms
from motoflex_ros.vehicle.dynamics import build_system
from motoflex_ros.vehicle.linearize import linearize
from motoflex_ros.vehicle.mode_names import STUDIED_MODES
from motoflex_ros.vehicle.model import load_vehicle, vehicle_from_dict
from motoflex_ros.vehicle.nonlinear_response import (
    RK4_RATE_LIMIT,
    nonlinear_steer_pulse,
    rk4_substeps,
)
from motoflex_ros.vehicle.steer_pulse import steer_pulse_response

SPEED = float(kmh_to_ms(100.0))


@pytest.fixture(scope="module")
def lin():
    return linearize(load_vehicle(config_path("vehicles", "touring")))


@pytest.fixture(scope="module")
def check(lin):
    return pulse_check(lin, SPEED)


def test_small_pulse_stays_small(check):
    """The review's pulse is a small motion: steer and roll below 2 deg."""
    assert check.torque == 20.0 and check.duration == pytest.approx(0.05)
    assert 0.0 < check.peak["steer"] < np.radians(2.0)
    assert 0.0 < check.peak["roll"] < np.radians(2.0)


def test_nonlinear_pulse_gives_weave_and_wobble_within_one_percent(check):
    assert set(check.linear) == set(STUDIED_MODES)
    for mode, (frequency, real) in check.relative_errors().items():
        assert abs(frequency) < 0.01, (mode, frequency)
        assert abs(real) < 0.01, (mode, real)


def test_nonlinear_response_follows_the_exact_linear_one(lin, check):
    """Same pulse through the linearization's exact zero-order-hold discretisation: every state
    within 1 % of its peak (the difference is the nonlinear terms and the Runge-Kutta step)."""
    linear = steer_pulse_response(lin, SPEED, check.torque, check.duration, t_end=1.5, dt=0.01,
                                  outputs=lin.state_names)
    response = check.response
    assert response.output_names == linear.output_names
    np.testing.assert_allclose(response.time, linear.time)
    scale = np.abs(linear.outputs).max(axis=0)
    assert np.all(np.abs(response.outputs - linear.outputs).max(axis=0) < 0.01 * scale)


def test_nonlinear_pulse_refuses_massless_bodies():
    """A massless body (as the lumped variants have) makes E singular: a clear ModelError."""
    with open(config_path("vehicles", "whipple_benchmark"), encoding="utf-8") as stream:
        data = yaml.safe_load(stream)
    data["bodies"]["dangling"] = {"mass": 0.0, "com": [1.0, 0.0, 0.6]}
    data["joints"]["dangling_hinge"] = {"type": "revolute", "parent": "rear_frame",
                                        "child": "dangling", "axis": [0.0, 1.0, 0.0],
                                        "point": [0.5, 0.0, 0.6], "stiffness": 300.0,
                                        "damping": 20.0}
    system = build_system(vehicle_from_dict(data, "dangling"))
    with pytest.raises(ModelError, match="E is singular"):
        nonlinear_steer_pulse(system, 5.0)


def test_nonlinear_pulse_names_an_unknown_output(lin):
    with pytest.raises(ModelError, match="no state 'pitch_rate'"):
        nonlinear_steer_pulse(lin.system, SPEED, outputs=["pitch_rate"])


def test_eig_pulse_check_json_carries_the_check(check):
    """``motoflex eig --pulse-check --json``'s entry: the same numbers as the core's check."""
    entry = pulse_check_to_json(check)
    assert entry["speed_mps"] == SPEED and entry["torque_nm"] == 20.0
    for mode, lam in check.linear.items():
        got = entry["modes"][mode]
        assert got["linear"] == [lam.real, lam.imag]
        assert got["nonlinear"] == [check.nonlinear[mode].real, check.nonlinear[mode].imag]
        assert (got["frequency_error"], got["real_error"]) == check.relative_errors()[mode]


@pytest.mark.parametrize("dt", [0.01, 0.05, 0.1])
def test_substeps_follow_the_fastest_eigenvalue(lin, dt):
    """The sub-step count comes from forward differences of the nonlinear derivative; it must
    match the largest |eigenvalue| of the complex-step linearization (123.7 1/s at 100 km/h):
    1, 4 and 7 Runge-Kutta steps per sample."""
    fastest = np.max(np.abs(lin.eigenvalues(SPEED)))
    assert rk4_substeps(lin.system, SPEED, dt) == int(np.ceil(fastest * dt / RK4_RATE_LIMIT))
