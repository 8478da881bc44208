"""Designs (factorial, sampled), Pearson coefficients (eqs. 16-17) and e_RMS% (eq. 18)."""
import numpy as np
import pytest

from motoflex_ros.errors import ConfigError, ModelError
from motoflex_ros.study.accuracy import rms_error_percent
from motoflex_ros.study.correlation import pearson, pearson_table
from motoflex_ros.study.factorial import (
    FACTORS,
    PAPER_TABLE2_NOMINAL,
    full_factorial,
    sampled_design,
)


def test_two_level_factorial_analytic():
    design = full_factorial(PAPER_TABLE2_NOMINAL, levels=2, rel_range=0.10)
    assert len(design) == 64 and design.factors == FACTORS
    # standard order: factor i alternates in blocks of 2^i
    for i in range(6):
        np.testing.assert_array_equal(design.coded[: 2 ** (i + 1), i],
                                      np.repeat([-1.0, 1.0], 2**i))
    assert np.unique(design.coded, axis=0).shape[0] == 64
    phys = design.physical
    assert phys[0, 2] == pytest.approx(0.9 * 5.95e3, rel=1e-15)
    assert phys[-1, 3] == pytest.approx(1.1 * 1.71e5, rel=1e-15)
    np.testing.assert_allclose(design.coded.T @ design.coded, 64 * np.eye(6))  # orthogonal
    block = design.values(8, 16)
    assert set(block) == set(FACTORS) and block["k_tf"].shape == (8,)


def test_three_level_factorial_analytic():
    design = full_factorial(PAPER_TABLE2_NOMINAL, levels=3, rel_range=0.30)
    assert len(design) == 729
    for i in range(6):
        values, counts = np.unique(design.coded[:, i], return_counts=True)
        np.testing.assert_array_equal(values, [-1.0, 0.0, 1.0])
        np.testing.assert_array_equal(counts, [243, 243, 243])
    assert design.physical[:, 0].min() == pytest.approx(0.7 * 3.75e5)


@pytest.mark.parametrize("method", ["sobol", "lhs", "random"])
def test_sampled_design_within_range_and_repeatable(method):
    first = sampled_design(PAPER_TABLE2_NOMINAL, 128, rel_range=0.3, method=method, seed=3)
    again = sampled_design(PAPER_TABLE2_NOMINAL, 128, rel_range=0.3, method=method, seed=3)
    assert first.coded.shape == (128, 6)
    assert np.all(np.abs(first.coded) <= 1.0)
    np.testing.assert_array_equal(first.coded, again.coded)
    # uniform on [-1, 1]: the mean of 128 points is near 0 (Sobol/LHS much nearer than random)
    assert np.all(np.abs(first.coded.mean(axis=0)) < 0.2)


def test_sampled_design_custom_sampler():
    def corners(n_runs, n_factors, seed):
        return np.tile([0.0, 1.0], (n_runs // 2 * n_factors)).reshape(n_runs, n_factors)

    design = sampled_design(PAPER_TABLE2_NOMINAL, 4, sampler=corners)
    assert design.kind == "corners" and set(np.unique(design.coded)) == {-1.0, 1.0}
    with pytest.raises(ConfigError, match="sampler"):
        sampled_design(PAPER_TABLE2_NOMINAL, 4, sampler=lambda n, d, s: np.full((n, d), 2.0))


@pytest.mark.parametrize(("kwargs", "key"), [({"levels": 1}, "levels"),
                                              ({"rel_range": 1.5}, "range")])
def test_factorial_bad_arguments(kwargs, key):
    with pytest.raises(ConfigError, match=key):
        full_factorial(PAPER_TABLE2_NOMINAL, **kwargs)


def test_factorial_missing_or_bad_nominal():
    nominal = dict(PAPER_TABLE2_NOMINAL)
    del nominal["k_bs"]
    with pytest.raises(ConfigError, match="k_bs"):
        full_factorial(nominal)
    with pytest.raises(ConfigError, match="nominal.k_ta"):
        full_factorial({**PAPER_TABLE2_NOMINAL, "k_ta": -1.0})


def test_pearson_equals_numpy_corrcoef():
    rng = np.random.default_rng(7)
    factors = rng.standard_normal((64, 6))
    indices = factors @ rng.standard_normal((6, 4)) + 0.3 * rng.standard_normal((64, 4))
    rho = pearson(factors, indices)
    reference = np.corrcoef(np.column_stack([indices, factors]), rowvar=False)[:4, 4:]
    np.testing.assert_allclose(rho, reference, rtol=0, atol=1e-14)


def test_pearson_of_design_signs_analytic():
    design = full_factorial(PAPER_TABLE2_NOMINAL, levels=2)
    x = design.coded
    # index = x_ba - 2 x_ta: rho = cov / (sigma_I sigma_F) = b_i / sqrt(sum b^2) (orthogonal)
    table = pearson_table(design, {"s": x[:, 3] - 2.0 * x[:, 2], "flat": np.ones(64)})
    assert table["s"]["k_ba"] == pytest.approx(1 / np.sqrt(5), abs=1e-14)
    assert table["s"]["k_ta"] == pytest.approx(-2 / np.sqrt(5), abs=1e-14)
    assert table["s"]["k_tf"] == pytest.approx(0.0, abs=1e-14)
    assert np.isnan(table["flat"]["k_tf"])
    # scale of the factor does not matter: physical levels give the same rho
    np.testing.assert_allclose(pearson(design.physical, x[:, 3] - 2 * x[:, 2])[0],
                               [table["s"][f] for f in FACTORS], atol=1e-12)


def test_rms_error_analytic():
    # sqrt((0 + 1 + 4) / 3) / 1 * 100
    assert rms_error_percent([1.0, 2.0, 3.0], [1.0, 1.0, 1.0]) == pytest.approx(
        100 * np.sqrt(5 / 3), rel=1e-15)
    # real parts: negative mean is taken in absolute value: 1 / 2 * 100
    assert rms_error_percent([-1.0, -3.0], [-2.0, -2.0]) == pytest.approx(50.0, rel=1e-15)


def test_rms_error_vectorised():
    rng = np.random.default_rng(2)
    flexible = rng.uniform(1, 2, (3, 4, 171))
    lumped = flexible * (1 + 0.01 * rng.standard_normal((3, 4, 171)))
    batched = rms_error_percent(lumped, flexible)
    assert batched.shape == (3, 4)
    assert batched[1, 2] == pytest.approx(rms_error_percent(lumped[1, 2], flexible[1, 2]))
    assert np.isinf(rms_error_percent([1.0, -1.0], [1.0, -1.0]))
    with pytest.raises(ModelError, match="same speeds"):
        rms_error_percent(np.zeros(3), np.zeros(4))
