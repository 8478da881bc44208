"""ANOVA of a factorial design against the closed-form sums of squares of a factorial."""
import numpy as np
import pytest

from motoflex_ros.errors import ModelError
from motoflex_ros.study.anova import anova, main_effect_share
from motoflex_ros.study.factorial import FACTORS, PAPER_TABLE2_NOMINAL, full_factorial

MAIN = np.array([0.8, -0.3, 1.7, -2.2, 0.05, 0.6])  # b_i, coded +/-1
INTERACTION = 0.4  # k_tf x k_ta
THREE_WAY = 0.15  # k_bf x k_ba x k_bs: not in the model -> residual


def synthetic_response(coded):
    x = coded
    return (3.0 + x @ MAIN + INTERACTION * x[:, 0] * x[:, 2]
            + THREE_WAY * x[:, 1] * x[:, 3] * x[:, 5])


def test_two_level_sums_of_squares_analytic():
    design = full_factorial(PAPER_TABLE2_NOMINAL, levels=2)
    result = anova(design.coded, synthetic_response(design.coded), design.factors)
    n = 64
    # two-level factorial: SS of a term with coefficient b on +/-1 columns is N b^2
    for name, b in zip(FACTORS, MAIN):
        assert result.sum_of_squares(name) == pytest.approx(n * b**2, abs=1e-9)
    assert result.sum_of_squares("k_tf:k_ta") == pytest.approx(n * INTERACTION**2, abs=1e-9)
    others = [t for t in result.terms if ":" in t and t != "k_tf:k_ta"]
    assert len(others) == 14
    assert max(result.sum_of_squares(t) for t in others) < 1e-9
    assert result.sum_of_squares("Residual") == pytest.approx(n * THREE_WAY**2, abs=1e-9)
    total = n * (np.sum(MAIN**2) + INTERACTION**2 + THREE_WAY**2)
    assert result.total_ss == pytest.approx(total, abs=1e-9)
    share = np.sum(MAIN**2) / (np.sum(MAIN**2) + INTERACTION**2 + THREE_WAY**2)
    assert result.main_share == pytest.approx(share, abs=1e-9)
    assert result.df[result.terms.index("Residual")] == 64 - 1 - 6 - 15


def test_three_level_main_effect_analytic():
    design = full_factorial(PAPER_TABLE2_NOMINAL, levels=3)
    x = design.coded
    y = 2.0 * x[:, 3] ** 2 - x[:, 3] + 0.5 * x[:, 0]  # quadratic in k_ba, linear in k_tf
    result = anova(x, y, design.factors)
    # categorical main effect: SS = (runs per level) * sum over levels of (level mean - mean)^2
    levels = np.array([-1.0, 0.0, 1.0])
    f = 2.0 * levels**2 - levels
    assert result.sum_of_squares("k_ba") == pytest.approx(243 * np.sum((f - f.mean()) ** 2),
                                                           abs=1e-9)
    assert result.sum_of_squares("k_tf") == pytest.approx(243 * 2 * 0.25, abs=1e-9)
    assert result.main_share == pytest.approx(1.0, abs=1e-12)


def test_main_effect_share_per_response():
    design = full_factorial(PAPER_TABLE2_NOMINAL, levels=2)
    x = design.coded
    shares = main_effect_share(design, {"additive": x @ MAIN,
                                        "pure_interaction": x[:, 0] * x[:, 1]})
    assert shares["additive"] == pytest.approx(1.0, abs=1e-12)
    assert shares["pure_interaction"] == pytest.approx(0.0, abs=1e-12)


def test_anova_rejects_non_factorial_design():
    rng = np.random.default_rng(1)
    with pytest.raises(ModelError, match="factorial"):
        anova(rng.uniform(-1, 1, (64, 6)), rng.standard_normal(64), FACTORS)


def test_anova_rejects_shape_mismatch():
    design = full_factorial(PAPER_TABLE2_NOMINAL, levels=2)
    with pytest.raises(ModelError, match="does not match"):
        anova(design.coded, np.zeros(63), FACTORS)


@pytest.mark.parametrize("levels", [2, 3])
def test_constant_response_has_the_same_table_shape(levels):
    design = full_factorial(PAPER_TABLE2_NOMINAL, levels=levels)
    varying = anova(design.coded, design.coded[:, 0], design.factors)
    constant = anova(design.coded, np.zeros(len(design)), design.factors)
    assert constant.terms == varying.terms
    np.testing.assert_array_equal(constant.df, varying.df)
    assert np.all(constant.sum_sq == 0) and np.isnan(constant.main_share)
