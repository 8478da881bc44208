"""The sensitivity pipeline on an analytic vehicle, in process and on Dask.

The "vehicle" is a 6-state system Q blockdiag(B_weave, B_wobble, B_other) Q^-1 with
B = [[sigma, w], [-w, sigma]] (eigenvalues sigma +/- i w) and sigma linear in speed and in
the coded stiffnesses, so every stability index has a closed form.
"""
from argparse import Namespace

import numpy as np
import pytest

from motoflex_ros.cli.study import extra_ranges
from motoflex_ros.errors import ConfigError, ModelError
from motoflex_ros.study.factorial import FACTORS, PAPER_TABLE2_NOMINAL, full_factorial
from motoflex_ros.study.runner import design_blocks, run_study
from motoflex_ros.study.sensitivity import analyse_sensitivity
from motoflex_ros.study.stability_index import speed_range
from motoflex_ros.study.tracked import HomotopyStart, NearestTargets, TrackedModeStudy

Q = (np.linalg.qr(np.random.default_rng(4).standard_normal((6, 6)))[0]
     + 0.2 * np.random.default_rng(5).standard_normal((6, 6)))
Q_INV = np.linalg.inv(Q)
W_WEAVE, W_WOBBLE = 2 * np.pi * 2.5, 2 * np.pi * 8.0
SPEEDS = np.linspace(40.0, 210.0, 171) / 3.6


def coded(values, name):
    return (values[name] / PAPER_TABLE2_NOMINAL[name] - 1.0) / 0.1


def sigma_weave(x, v):
    """Weave real part [1/s]: rises with speed; k_ba up damps, k_bs up destabilises."""
    return -0.6 + 0.012 * v + 0.05 * x["k_bs"] - 0.1 * x["k_ba"]


def sigma_wobble(x, v):
    """Wobble real part [1/s]: k_ta up destabilises; k_ba changes the slope over speed."""
    return -1.5 + (0.01 + 0.02 * x["k_ba"]) * v + 0.2 * x["k_ta"]


def analytic_state_matrices(values, speed):
    x = {name: coded(values, name) for name in FACTORS}
    runs = len(values["k_tf"])
    d = np.zeros((runs, 6, 6))
    for i, (sigma, w) in enumerate([(sigma_weave(x, speed), W_WEAVE),
                                    (sigma_wobble(x, speed), W_WOBBLE),
                                    (np.full(runs, -4.0), 30.0)]):
        d[:, 2 * i, 2 * i] = d[:, 2 * i + 1, 2 * i + 1] = sigma
        d[:, 2 * i, 2 * i + 1], d[:, 2 * i + 1, 2 * i] = w, -w
    return Q @ d @ Q_INV


STUDY = TrackedModeStudy(state_matrices=analytic_state_matrices, speeds=tuple(SPEEDS),
                         start=NearestTargets(targets=(-0.1 + W_WEAVE * 1j,
                                                       -1.0 + W_WOBBLE * 1j)))


def analytic_index(sigma, x, v_range):
    """Index s for a real part linear in speed: max at an end; one crossing at most."""
    lo, hi = sigma(x, v_range[0]), sigma(x, v_range[1])
    s1 = np.maximum(lo, hi)
    stable_share = np.clip(np.where(lo * hi < 0, np.maximum(-lo, 0) / np.abs(hi - lo)
                                    + np.maximum(-hi, 0) / np.abs(hi - lo), 1.0), 0, 1)
    s2 = np.where((lo > 0) & (hi > 0), 0.0, stable_share)
    return np.abs(np.minimum(0, s1)) + s2


@pytest.fixture(scope="module")
def design():
    return full_factorial(PAPER_TABLE2_NOMINAL, levels=2, rel_range=0.10)


@pytest.fixture(scope="module")
def in_process(design):
    return run_study(STUDY, design, progress=False, block_size=16)


def test_tracked_modes_analytic(design, in_process):
    x = {name: design.coded[:, i] for i, name in enumerate(design.factors)}
    weave = in_process.outputs["weave"]
    assert weave.shape == (64, 171)
    np.testing.assert_allclose(weave.real, sigma_weave(x, SPEEDS[None, :].T).T, atol=1e-10)
    np.testing.assert_allclose(weave.imag, W_WEAVE, atol=1e-10)
    np.testing.assert_allclose(in_process.outputs["wobble"].real,
                               sigma_wobble(x, SPEEDS[None, :].T).T, atol=1e-10)


def test_sensitivity_indices_analytic(design, in_process):
    result = analyse_sensitivity(design, SPEEDS, in_process.outputs)
    x = {name: design.coded[:, i] for i, name in enumerate(design.factors)}
    for mode, sigma in (("weave", sigma_weave), ("wobble", sigma_wobble)):
        for name in ("low", "high"):
            expected = analytic_index(sigma, x, speed_range(name))
            np.testing.assert_allclose(result.indices[f"{mode}_{name}"].s, expected,
                                       atol=1e-9)
    # weave crosses at high speed in some runs (s < 1), never at low speed (s > 1)
    assert np.any(result.indices["weave_high"].s < 1) and np.all(
        result.indices["weave_low"].s > 1)
    rho = result.pearson
    assert rho["weave_high"]["k_ba"] > 0.5 and rho["weave_high"]["k_bs"] < -0.2
    assert rho["wobble_low"]["k_ta"] < -0.1 and rho["wobble_high"]["k_ta"] < -0.1
    # k_ba steepens wobble's rise with speed: destabilising, most at high speed
    assert rho["wobble_high"]["k_ba"] < -0.5
    assert abs(rho["wobble_low"]["k_tf"]) < 1e-12
    shares = result.anova_main_share
    assert set(shares) == {"weave_low", "weave_high", "wobble_low", "wobble_high"}
    assert shares["weave_low"] == pytest.approx(1.0, abs=1e-12)  # additive in the factors
    data = result.to_dict()
    assert set(data) == {"nominal", "indices", "anova_main_share", "pearson"}
    assert len(data["indices"]["wobble_high"]) == 64


def test_extra_speed_range_indices_analytic(design, in_process):
    """Issue 22 (3): an extra range (40-95 km/h) adds "<mode>_40-95kmh" indices equal to the
    closed form on that range, and leaves the paper's four unchanged."""
    plain = analyse_sensitivity(design, SPEEDS, in_process.outputs)
    result = analyse_sensitivity(design, SPEEDS, in_process.outputs, extra_ranges_kmh=[(40, 95)])
    assert list(result.indices) == list(plain.indices) + ["weave_40-95kmh", "wobble_40-95kmh"]
    for name, index in plain.indices.items():
        np.testing.assert_array_equal(result.indices[name].s, index.s)
    x = {name: design.coded[:, i] for i, name in enumerate(design.factors)}
    for mode, sigma in (("weave", sigma_weave), ("wobble", sigma_wobble)):
        expected = analytic_index(sigma, x, (40.0 / 3.6, 95.0 / 3.6))
        np.testing.assert_allclose(result.indices[f"{mode}_40-95kmh"].s, expected, atol=1e-9)
    assert set(result.pearson["wobble_40-95kmh"]) == set(design.factors)


def test_extra_speed_range_outside_the_grid_is_a_config_error():
    assert extra_ranges(Namespace(extra_range_kmh=[[40.0, 95.0]])) == [(40.0, 95.0)]
    for bad in ([30.0, 95.0], [95.0, 40.0], [40.0, 220.0]):
        with pytest.raises(ConfigError, match="--extra-range-kmh"):
            extra_ranges(Namespace(extra_range_kmh=[bad]))


def test_dask_path_identical_to_in_process(design, in_process):
    from distributed import Client, LocalCluster

    with LocalCluster(n_workers=2, threads_per_worker=1, processes=False,
                      dashboard_address=None) as cluster, Client(cluster) as client:
        on_dask = run_study(STUDY, design, scheduler=client, progress=False, block_size=16)
    assert on_dask.where.startswith(("inproc://", "tcp://"))
    assert set(on_dask.outputs) == set(in_process.outputs)
    for name, values in in_process.outputs.items():
        np.testing.assert_array_equal(on_dask.outputs[name], values)


@pytest.fixture(scope="module")
def motorcycle_study():
    """The real study function: the decomposed lumped touring motorcycle with the paper's
    Table 2 stiffnesses on the components' finite-element torsion and bending axes (no bench
    run), 40-210 km/h every 10 km/h."""
    from motoflex_ros.cli.inputs import motorcycle_components, study_speeds
    from motoflex_ros.config import resolve_config
    from motoflex_ros.study.motorcycle import decomposed_study, with_stiffness
    from motoflex_ros.vehicle.model import load_vehicle

    components = motorcycle_components()
    reduced = {name: component.clamped_reduced() for name, component in components.items()}
    axes = {name: {test: {"l": float(r.mode_axis(test).l), "beta": float(r.mode_axis(test).beta)}
                   for test in ("torsion", "bending")} for name, r in reduced.items()}
    vehicle = load_vehicle(resolve_config("vehicles", "touring"))
    return decomposed_study(vehicle, components, with_stiffness(axes, PAPER_TABLE2_NOMINAL),
                            study_speeds(10.0, 10.0)).study


@pytest.mark.slow  # starting two worker processes: ~20 s on the shared 2-core machine
def test_dask_worker_processes_identical_to_in_process(motorcycle_study):
    """Two single-threaded worker processes (the runner's LocalCluster) give the real study's
    eigenvalues bit for bit as in this process, four blocks of 16 runs."""
    import os

    from distributed import Client

    from motoflex_ros.study.runner import local_cluster

    design = full_factorial(PAPER_TABLE2_NOMINAL, levels=2, rel_range=0.10)
    in_process = run_study(motorcycle_study, design, progress=False, block_size=16)
    with local_cluster(n_workers=2, processes=True) as cluster, Client(cluster) as client:
        worker_pids = client.run(os.getpid)
        on_dask = run_study(motorcycle_study, design, scheduler=client, progress=False,
                            block_size=16)
    assert len(worker_pids) == 2 and os.getpid() not in worker_pids.values()
    assert on_dask.where.startswith("tcp://")
    assert set(on_dask.outputs) == set(in_process.outputs) >= {"weave", "wobble"}
    for name, values in in_process.outputs.items():
        np.testing.assert_array_equal(on_dask.outputs[name], values)


def test_blocks_cover_the_design_once():
    assert design_blocks(10, 4) == [(0, 4), (4, 8), (8, 10)]
    with pytest.raises(ModelError, match="block size"):
        design_blocks(10, 0)


def test_study_function_must_return_runs(design):
    with pytest.raises(ModelError, match="expected"):
        run_study(lambda values: {"bad": np.zeros(3)}, design, progress=False)
    with pytest.raises(ModelError, match="mapping"):
        run_study(lambda values: np.zeros(64), design, progress=False)


def rotating_state_matrices(values, speed):
    """The analytic vehicle with weave and wobble shapes turning into each other with speed.

    The planes of coordinates (0, 2) and (1, 3) turn by speed / 15 rad (speed in m/s).
    """
    c, s = np.cos(speed / 15.0), np.sin(speed / 15.0)
    rotation = np.eye(6)
    for i, j in ((0, 2), (1, 3)):
        rotation[np.ix_([i, j], [i, j])] = [[c, -s], [s, c]]
    return rotation @ analytic_state_matrices(values, speed) @ rotation.T


def test_too_coarse_grid_is_reported(design):
    start = NearestTargets(targets=(-0.1 + W_WEAVE * 1j, -1.0 + W_WOBBLE * 1j))
    fine = TrackedModeStudy(state_matrices=rotating_state_matrices, speeds=tuple(SPEEDS),
                            start=start)
    assert fine(design.values(0, 4))["weave_step_mac"].min() > 0.99
    coarse = TrackedModeStudy(state_matrices=rotating_state_matrices,
                              speeds=tuple(SPEEDS[::85]), start=start)
    with pytest.raises(ModelError, match="finer speed grid|did not converge"):
        coarse(design.values(0, 4))


def swapping_state_matrices(values, speed):
    """Two modes whose frequencies swap order when k_ta goes up by 30 %: -1 + (5 + 3 x) i and
    -1.2 + 6.5 i, with x the coded k_ta at +/-30 %, fixed mode shapes."""
    x = (values["k_ta"] / PAPER_TABLE2_NOMINAL["k_ta"] - 1.0) / 0.3
    runs = x.size
    d = np.zeros((runs, 6, 6))
    for i, (sigma, w) in enumerate([(np.full(runs, -1.0), 5.0 + 3.0 * x),
                                    (np.full(runs, -1.2), np.full(runs, 6.5)),
                                    (np.full(runs, -4.0), np.full(runs, 30.0))]):
        d[:, 2 * i, 2 * i] = d[:, 2 * i + 1, 2 * i + 1] = sigma
        d[:, 2 * i, 2 * i + 1], d[:, 2 * i + 1, 2 * i] = w, -w
    return Q @ d @ Q_INV


def test_homotopy_start_keeps_mode_identity_analytic():
    design = full_factorial(PAPER_TABLE2_NOMINAL, levels=2, rel_range=0.3)
    values = design.values()
    nominal = {name: np.array([v]) for name, v in PAPER_TABLE2_NOMINAL.items()}
    targets = (-1.0 + 5.0j, -1.2 + 6.5j)
    start = HomotopyStart(nominal=swapping_state_matrices(nominal, SPEEDS[0])[0],
                          targets=targets)
    lam, vec = start(swapping_state_matrices(values, SPEEDS[0]))
    x = design.coded[:, design.factors.index("k_ta")]
    np.testing.assert_allclose(lam[:, 0], -1.0 + (5.0 + 3.0 * x) * 1j, atol=1e-10)
    np.testing.assert_allclose(lam[:, 1], -1.2 + 6.5j, atol=1e-10)
    # picking the nearest eigenvalue confuses the two modes where k_ta is high
    with pytest.raises(ModelError, match="same eigenvalue"):
        NearestTargets(targets=targets)(swapping_state_matrices(values, SPEEDS[0]))
