"""The vehicle-to-study plug: linear stiffness pencils with a massless coordinate."""
import numpy as np
import pytest
import scipy.linalg

from motoflex_ros.errors import ModelError
from motoflex_ros.study.continuation import mac
from motoflex_ros.study.factorial import FACTORS, PAPER_TABLE2_NOMINAL, full_factorial
from motoflex_ros.study.tracked import (
    HomotopyStart,
    LinearStiffnessPencil,
    NearestTargets,
    TrackedModeStudy,
    stiffness_directions,
)

RNG = np.random.default_rng(17)
NQ = 4
MASS = np.diag([1.0, 2.0, 1.5, 0.0])  # last coordinate massless: E is singular
SPRINGS = RNG.standard_normal((6, NQ))
K_BASE = 50.0 * np.eye(NQ)
DAMPING = 0.4 * np.eye(NQ) + 0.1 * np.ones((NQ, NQ))
GYRO = np.array([[0, 1.0, 0, 0], [-1.0, 0, 0.5, 0], [0, -0.5, 0, 0], [0, 0, 0, 0]])
K2 = 0.01 * RNG.standard_normal((NQ, NQ))


def stiffness(k):
    """K(k) = K_base + sum_i 40 k_i / k_nom,i s_i s_i^T [N m/rad]."""
    total = K_BASE.copy()
    for i, name in enumerate(FACTORS):
        total += 40.0 * k[name] / PAPER_TABLE2_NOMINAL[name] * np.outer(SPRINGS[i], SPRINGS[i])
    return total


def state_coefficient(k, power):
    """Coefficient of v^power of A(v; k) for the state (q, u)."""
    a = np.zeros((2 * NQ, 2 * NQ))
    if power == 0:
        a[:NQ, NQ:] = np.eye(NQ)
        a[NQ:, :NQ], a[NQ:, NQ:] = -stiffness(k), -DAMPING
    elif power == 1:
        a[NQ:, NQ:] = -GYRO
    else:
        a[NQ:, :NQ] = -K2
    return a


E0 = scipy.linalg.block_diag(np.eye(NQ), MASS)


def pencil_of_vehicle():
    nominal = dict(PAPER_TABLE2_NOMINAL)
    a_coeffs = np.stack([state_coefficient(nominal, p) for p in range(3)])
    e_coeffs = np.stack([E0, np.zeros_like(E0), np.zeros_like(E0)])
    directions = stiffness_directions(lambda k: state_coefficient(k, 0), nominal)
    return LinearStiffnessPencil(e_coeffs, a_coeffs, directions, nominal)


def test_directions_are_the_stiffness_derivatives_analytic():
    directions = stiffness_directions(lambda k: state_coefficient(k, 0), PAPER_TABLE2_NOMINAL)
    for i, name in enumerate(FACTORS):
        expected = np.zeros((2 * NQ, 2 * NQ))
        expected[NQ:, :NQ] = -40.0 / PAPER_TABLE2_NOMINAL[name] * np.outer(SPRINGS[i],
                                                                               SPRINGS[i])
        np.testing.assert_allclose(directions[name], expected, rtol=1e-9,
                                   atol=1e-12 * np.abs(expected).max())


def test_nonlinear_stiffness_is_refused():
    with pytest.raises(ModelError, match="not linear in stiffness k_tf"):
        stiffness_directions(lambda k: np.array([[k["k_tf"] ** 2 / 1e10]]),
                             {"k_tf": 3.75e5})


def finite_eigenvalues(a, e):
    values = scipy.linalg.eig(a, e, right=False)
    return values[np.isfinite(values)]


def nominal_targets(speed):
    """Highest- and lowest-frequency oscillatory modes of the nominal pencil at ``speed``."""
    k = PAPER_TABLE2_NOMINAL
    values = finite_eigenvalues(sum(speed**p * state_coefficient(k, p) for p in range(3)), E0)
    assert values.size == 2 * NQ - 1  # one first-order mode from the massless coordinate
    upper = np.sort_complex(values[values.imag > 0] * 1j) / 1j
    return (upper[-1], upper[0])


def test_tracked_pencil_study_matches_scipy_generalized_eig():
    pencil = pencil_of_vehicle()
    speeds = np.linspace(5.0, 40.0, 71)
    study = TrackedModeStudy(state_matrices=pencil, speeds=tuple(speeds),
                             start=NearestTargets(targets=nominal_targets(speeds[0])))
    design = full_factorial(PAPER_TABLE2_NOMINAL, levels=2)
    values = design.values(0, 8)
    out = study(values)
    for r in range(8):
        k = {name: values[name][r] for name in FACTORS}
        current = np.array([out["weave"][r, 0], out["wobble"][r, 0]])
        for j, v in enumerate(speeds):
            a = sum(v**p * state_coefficient(k, p) for p in range(3))
            reference = finite_eigenvalues(a, E0)
            current = reference[np.argmin(np.abs(reference[:, None] - current), axis=0)]
            np.testing.assert_allclose([out["weave"][r, j], out["wobble"][r, j]], current,
                                       atol=1e-9)


@pytest.mark.slow
def test_local_process_cluster_single_thread_blas_and_identical_results():
    """A study of arrays only (picklable by reference) on a 1-process LocalCluster."""
    import os

    from distributed import Client

    from motoflex_ros.study.runner import local_cluster, run_study

    study = TrackedModeStudy(state_matrices=pencil_of_vehicle(),
                             speeds=tuple(np.linspace(5.0, 40.0, 36)),
                             start=NearestTargets(targets=nominal_targets(5.0)))
    design = full_factorial(PAPER_TABLE2_NOMINAL, levels=2)
    here = run_study(study, design, progress=False, block_size=16)
    with local_cluster(n_workers=1) as cluster, Client(cluster) as client:
        env = client.run(os.getenv, "OPENBLAS_NUM_THREADS")
        there = run_study(study, design, scheduler=cluster, progress=False, block_size=16)
    assert list(env.values()) == ["1"]
    for name, values in here.outputs.items():
        np.testing.assert_array_equal(there.outputs[name], values)


def test_homotopy_start_on_pencils_equals_nearest_pick():
    pencil = pencil_of_vehicle()
    design = full_factorial(PAPER_TABLE2_NOMINAL, levels=2)
    nominal = {name: np.array([v]) for name, v in PAPER_TABLE2_NOMINAL.items()}
    e_nom, a_nom = pencil(nominal, 5.0)
    targets = nominal_targets(5.0)
    runs = pencil(design.values(), 5.0)
    homotopy = HomotopyStart(nominal=(e_nom[0], a_nom[0]), targets=targets)(runs)
    nearest = NearestTargets(targets=targets)(runs)
    np.testing.assert_allclose(homotopy[0], nearest[0], atol=1e-10)
    np.testing.assert_allclose(mac(homotopy[1], nearest[1]), 1.0, atol=1e-10)


def test_sensitivity_end_to_end_equals_full_eig_tracking():
    import json

    from motoflex_ros.study.sensitivity import run_sensitivity, stability_indices
    from motoflex_ros.study.tracked import pencil_study

    nominal = dict(PAPER_TABLE2_NOMINAL)
    speeds = np.linspace(40.0, 210.0, 35) / 3.6
    a_coeffs = np.stack([state_coefficient(nominal, p) for p in range(3)])
    e_coeffs = np.stack([E0, 0 * E0, 0 * E0])
    study = pencil_study(e_coeffs, a_coeffs, lambda k: state_coefficient(k, 0), nominal,
                         speeds, nominal_targets(speeds[0]))
    result, run = run_sensitivity(study, nominal, speeds, progress=False)
    design = run.design
    # reference: generalized eig (QZ) at every speed, nearest-eigenvalue following
    reference = {"weave": [], "wobble": []}
    for r in range(len(design)):
        k = {name: design.physical[r, i] for i, name in enumerate(design.factors)}
        current = np.array([run.outputs["weave"][r, 0], run.outputs["wobble"][r, 0]])
        curve = []
        for v in speeds:
            values = finite_eigenvalues(sum(v**p * state_coefficient(k, p) for p in range(3)),
                                        E0)
            current = values[np.argmin(np.abs(values[:, None] - current), axis=0)]
            curve.append(current)
        reference["weave"].append(np.array(curve)[:, 0])
        reference["wobble"].append(np.array(curve)[:, 1])
    expected = stability_indices(speeds, {m: np.array(c) for m, c in reference.items()})
    for name, index in expected.items():
        np.testing.assert_allclose(result.indices[name].s, index.s, rtol=1e-9, atol=1e-12)
    text = json.dumps(result.to_dict(), allow_nan=False)
    assert json.loads(text)["nominal"]["k_ba"] == 1.71e5
