"""Touring motorcycle (config/vehicles/touring.yaml): mass budget, speed polynomial, and weave /
wobble / capsize tracked over 40-210 km/h against the published trends.

Published trends, reference/motorcycle-data.md sect. 2f: weave 1-4 Hz and wobble 6-10 Hz
(Passigato et al. 2023, introduction); Cossalter 4-dof model: wobble 8.5-9.6 Hz with little speed
effect, weave frequency rising with speed to about 3.6 Hz, lightly damped at high speed.
"""
import numpy as np
import pytest

from motoflex_ros.config import config_path
from motoflex_ros.vehicle.linearize import linearize, linearize_at
from motoflex_ros.vehicle.model import load_vehicle
from motoflex_ros.vehicle.modes import modal_sweep

KMH = np.arange(40.0, 210.0 + 1e-9, 1.0)


@pytest.fixture(scope="module")
def touring():
    return load_vehicle(config_path("vehicles", "touring"))


@pytest.fixture(scope="module")
def lin(touring):
    return linearize(touring)


@pytest.fixture(scope="module")
def sweep(lin):
    return modal_sweep(lin, KMH / 3.6)


def test_mass_budget_published(touring):
    """Paper sect. 3: 250 kg motorcycle, 88 kg rider, 40 kg luggage."""
    assert touring.total_mass() == pytest.approx(378.0, abs=0.01)
    frame = touring.body("frame")
    rider = touring.body("rider_upper_body").mass + 22.2742
    luggage = 12.5 + 12.5 + 15.0
    assert rider == pytest.approx(88.0, abs=1e-3)
    assert touring.total_mass() - rider - luggage == pytest.approx(250.0, abs=0.01)
    # [TUM]'s frame x s = 193.4482 kg, of which the Telelever arm is now its own body
    arm = touring.body("telelever_arm").mass
    assert frame.mass + arm == pytest.approx(193.4482 + 22.2742 + luggage)
    paralever = sum(touring.body(n).mass for n in ("swingarm", "torque_strut", "wheel_carrier"))
    assert paralever == pytest.approx(8.0 * 1.25848, abs=1e-4)     # [TUM] swingarm x s


def test_inertias_physical(touring):
    for body in touring.bodies:
        moments = np.linalg.eigvalsh(body.inertia)
        assert moments[0] > 0
        assert moments[0] + moments[1] >= moments[2]


def test_speed_polynomial_roundtrip(lin):
    """E(v), A(v) from three linearizations equal a direct one at 150 km/h (MF sigma(v))."""
    v = 150.0 / 3.6
    E, A = linearize_at(lin.system, v)
    E_fit, A_fit = lin.pencil([v])
    np.testing.assert_allclose(E_fit[0], E, rtol=1e-9, atol=1e-9 * np.abs(E).max())
    np.testing.assert_allclose(A_fit[0], A, rtol=1e-9, atol=1e-9 * np.abs(A).max())


@pytest.mark.parametrize("name, band", [("weave", (0.5, 5.0)), ("wobble", (5.0, 12.0))])
def test_modes_tracked_in_band(sweep, name, band):
    freq = sweep.frequency_hz(name)
    assert np.all(np.isfinite(sweep.modes[name])), f"{name} lost at some speed"
    assert np.all((freq >= band[0]) & (freq <= band[1]))
    # continuity on a 1 km/h grid: no jump to another mode
    assert np.max(np.abs(np.diff(sweep.modes[name]))) < 0.6


def test_capsize_reported(sweep):
    assert np.all(np.isfinite(sweep.modes["capsize"]))
    assert np.all(sweep.modes["capsize"].imag == 0.0)


def test_trends_published(sweep):
    weave_f, wobble_f = sweep.frequency_hz("weave"), sweep.frequency_hz("wobble")
    assert np.all(np.diff(weave_f) > 0), "weave frequency rises with speed"
    assert 2.5 < weave_f[-1] < 4.0
    assert 8.0 < wobble_f.min() and wobble_f.max() < 10.0, "wobble 8-10 Hz, little speed effect"
    weave_re = sweep.real_part("weave")
    assert weave_re[-1] > weave_re[KMH == 100.0][0], "weave less damped at high speed"


def test_mode_shapes_are_eigenvectors_roundtrip(lin, sweep):
    """The reported shapes satisfy E(v) lambda phi = A(v) phi; wobble is steer-dominated."""
    k = int(np.argmin(np.abs(KMH - 150.0)))
    E, A = lin.pencil([KMH[k] / 3.6])
    steer = lin.state_names.index("steer_rate")
    for name in ("weave", "wobble", "capsize"):
        lam, phi = sweep.modes[name][k], sweep.mode_shapes[name][k]
        np.testing.assert_allclose(lam * E[0] @ phi, A[0] @ phi, atol=1e-8 * np.abs(A).max())
    rates = [i for i, n in enumerate(lin.state_names) if n.endswith("_rate")]
    wobble = np.abs(sweep.mode_shapes["wobble"][k][rates])
    assert np.argmax(wobble) == rates.index(steer)
