"""Virtual road test: steer-pulse response of the touring motorcycle, weave and wobble
identified back from it by the matrix pencil and compared with the eigenvalues (issue 5: within
2 %), and the exact discretisation checked against an ODE solver."""
import numpy as np
import pytest
from scipy.integrate import solve_ivp

from motoflex_ros.config import config_path
from motoflex_ros.errors import ModelError
from motoflex_ros.identify.matrix_pencil import matrix_pencil_poles, unit_peak
from motoflex_ros.vehicle.linearize import linearize
from motoflex_ros.vehicle.model import load_vehicle
from motoflex_ros.vehicle.modes import modal_sweep
from motoflex_ros.vehicle.steer_pulse import joint_input, steer_pulse_response

DT = 0.005


@pytest.fixture(scope="module")
def lin():
    return linearize(load_vehicle(config_path("vehicles", "touring")))


def _identified(lin, kmh, noise=0.0, seed=0):
    speed = kmh / 3.6
    response = steer_pulse_response(lin, speed, dt=DT)
    free = response.outputs[response.time >= response.duration]
    if noise:
        rng = np.random.default_rng(seed)
        free = free + noise * np.abs(free).max(axis=0) * rng.standard_normal(free.shape)
    order = lin.system.n_states if noise else None
    poles = matrix_pencil_poles(unit_peak(free), DT, order=order)
    return poles, modal_sweep(lin, [speed])


def _closest(poles, target):
    return poles[np.argmin(np.abs(poles - target))]


@pytest.mark.parametrize("kmh", [60.0, 100.0, 150.0, 200.0])
def test_pencil_recovers_eigenvalues_roundtrip(lin, kmh):
    poles, sweep = _identified(lin, kmh)
    for name in ("weave", "wobble"):
        want = sweep.modes[name][0]
        got = _closest(poles, want)
        assert abs(got.imag - want.imag) <= 0.02 * want.imag
        assert abs(got.real - want.real) <= 0.02 * abs(want.real)
        assert abs(got - want) < 1e-6 * abs(want)    # noise-free: exact to rounding


@pytest.mark.parametrize("kmh", [60.0, 100.0, 150.0])
def test_pencil_with_sensor_noise_within_two_percent(lin, kmh):
    """0.1 % white noise on steer angle, roll and yaw rate: frequency and damping ratio within
    2 % of the eigenvalues."""
    poles, sweep = _identified(lin, kmh, noise=1e-3, seed=int(kmh))
    for name in ("weave", "wobble"):
        want = sweep.modes[name][0]
        got = _closest(poles, want)
        assert abs(got.imag - want.imag) <= 0.02 * want.imag
        zeta_got, zeta_want = -got.real / abs(got), -want.real / abs(want)
        assert abs(zeta_got - zeta_want) <= 0.02 * abs(zeta_want)


def test_exact_discretisation_matches_ode_solver(lin):
    speed = 100.0 / 3.6
    response = steer_pulse_response(lin, speed, torque=20.0, duration=0.05, t_end=1.0, dt=DT)
    E, A = lin.pencil([speed])
    a = np.linalg.solve(E[0], A[0])
    b = np.linalg.solve(E[0], joint_input(lin, "steer"))

    def rhs(t, x):
        return a @ x + b * (20.0 if t < 0.05 else 0.0)

    first = solve_ivp(rhs, (0.0, 0.05), np.zeros(len(b)), rtol=1e-11, atol=1e-13,
                      method="DOP853")
    second = solve_ivp(rhs, (0.05, 1.0), first.y[:, -1], rtol=1e-11, atol=1e-13,
                       method="DOP853", t_eval=response.time[response.time >= 0.05])
    rows = [lin.state_names.index(n) for n in response.output_names]
    want = second.y[rows].T
    got = response.outputs[response.time >= 0.05]
    np.testing.assert_allclose(got, want, atol=1e-8 * np.abs(want).max())


def test_default_outputs_and_unknown_output_named():
    """Knife-edge wheels (Whipple bicycle): the default outputs are steer angle and roll rate
    (yaw rate is not a state there), and asking for yaw rate names it and the states."""
    bicycle = linearize(load_vehicle(config_path("vehicles", "whipple_benchmark")))
    response = steer_pulse_response(bicycle, 5.0, t_end=0.1)
    assert response.output_names == (bicycle.system.model.roles["steer"], "roll_rate")
    with pytest.raises(ModelError, match=r"no state 'yaw_rate'.*not states.*roll_rate"):
        steer_pulse_response(bicycle, 5.0, t_end=0.1, outputs=["yaw_rate"])


def test_default_outputs_with_tyres_include_yaw_rate(lin):
    response = steer_pulse_response(lin, 20.0, t_end=0.1)
    assert response.output_names == ("steer", "roll_rate", "yaw_rate")
