"""Analysis of variance of a stability index over a factorial design (Sect. 4.3, step 2).

The paper runs MATLAB's ``anovan`` with main effects and two-factor interactions and reports
the share of the index's variability due to main effects (about 99 %, Sect. 5.3). Here the
same model is fitted with statsmodels (ols + anova_lm, type-2 sums of squares) on the coded
design, every factor treated as categorical (sum-to-zero coding), as ``anovan`` does. For a
two-level factorial this equals the classical effects model; for three levels each main
effect has two degrees of freedom (linear and quadratic parts). Everything not in the model
(three-factor and higher interactions) is the residual.

The main-effect share is sum(SS_main) / SS_total with SS_total = sum((y - mean y)^2). In an
orthogonal (full factorial) design the type-2 sums of squares of all terms and the residual
add up to SS_total exactly.
"""
import re
import warnings
from dataclasses import dataclass

import numpy as np
import pandas as pd
import statsmodels.formula.api as smf
from statsmodels.stats.anova import anova_lm

from motoflex_ros.errors import ModelError

__all__ = ["AnovaResult", "anova", "main_effect_share"]

_MAX_LEVELS = 10
_TERM = re.compile(r"C\((\w+), Sum\)")


@dataclass(frozen=True, eq=False)
class AnovaResult:
    """ANOVA table of one response.

    terms: factor names and "a:b" interactions, then "Residual"; sum_sq [response unit^2],
    df, f_value, p_value: one per term (F and p are NaN for the residual); total_ss: corrected
    total sum of squares; main_share: sum of the main effects' sums of squares / total_ss.
    """

    terms: tuple
    sum_sq: np.ndarray
    df: np.ndarray
    f_value: np.ndarray
    p_value: np.ndarray
    total_ss: float
    main_share: float

    def sum_of_squares(self, term):
        """Sum of squares of one term, e.g. "k_ta" or "k_tf:k_bf"."""
        return float(self.sum_sq[self.terms.index(term)])


def _formula(factors, interactions):
    main = " + ".join(f"C({name}, Sum)" for name in factors)
    return f"response ~ ({main})**2" if interactions else f"response ~ {main}"


def _check_factorial(coded, factors):
    for i, name in enumerate(factors):
        if np.unique(coded[:, i]).size > _MAX_LEVELS:
            raise ModelError(f"ANOVA needs a factorial design: factor {name} has more than "
                             f"{_MAX_LEVELS} levels")


def _constant_response(coded, factors, interactions):
    """The ANOVA table of a response that does not vary: all zero, share undefined (NaN)."""
    free = {name: np.unique(coded[:, i]).size - 1.0 for i, name in enumerate(factors)}
    terms, df = list(factors), [free[name] for name in factors]
    if interactions:
        for i, a in enumerate(factors):
            for b in factors[i + 1:]:
                terms.append(f"{a}:{b}")
                df.append(free[a] * free[b])
    terms.append("Residual")
    df.append(coded.shape[0] - 1.0 - sum(df))
    nan = np.full(len(terms), np.nan)
    return AnovaResult(terms=tuple(terms), sum_sq=np.zeros(len(terms)), df=np.array(df),
                       f_value=nan, p_value=nan, total_ss=0.0, main_share=float("nan"))


def anova(coded, response, factors, interactions=True):
    """ANOVA with main effects and (optionally) all two-factor interactions.

    Parameters
    ----------
    coded : array (runs, factors)
        Coded factor levels of a factorial design.
    response : array (runs,)
        The response (e.g. a stability index, eq. 15).
    factors : sequence of str
        Factor names (valid Python identifiers), in column order.
    interactions : bool
        Include the two-factor interactions (the paper's model).

    Returns
    -------
    AnovaResult
        Sums of squares [response unit^2], degrees of freedom, F and p per term, the total sum
        of squares and the main-effect share [-].

    Examples
    --------
    A 2^3 design with the response 3 a + b + 0.5 a b: over the eight runs at +/-1 the sums of
    squares are 8 x 3^2 = 72 for a, 8 for b, 8 x 0.5^2 = 2 for a:b and 0 for c, so the main
    effects carry 80 of the total 82:

    >>> import itertools
    >>> coded = np.array(list(itertools.product([-1.0, 1.0], repeat=3)))
    >>> y = 3 * coded[:, 0] + coded[:, 1] + 0.5 * coded[:, 0] * coded[:, 1]
    >>> result = anova(coded, y, ("a", "b", "c"))
    >>> [round(result.sum_of_squares(t), 9) + 0.0 for t in ("a", "b", "c", "a:b")]
    [72.0, 8.0, 0.0, 2.0]
    >>> round(result.main_share * 82, 9)
    80.0

    """
    coded = np.asarray(coded, dtype=float)
    response = np.asarray(response, dtype=float)
    factors = tuple(factors)
    if coded.ndim != 2 or coded.shape != (response.size, len(factors)):
        raise ModelError(f"design {coded.shape} does not match {response.size} responses and "
                         f"{len(factors)} factors")
    _check_factorial(coded, factors)
    if np.ptp(response) == 0.0:
        return _constant_response(coded, factors, interactions)
    frame = pd.DataFrame(coded, columns=list(factors))
    frame["response"] = response
    fit = smf.ols(_formula(factors, interactions), data=frame).fit()
    with warnings.catch_warnings(), np.errstate(divide="ignore", invalid="ignore"):
        warnings.simplefilter("ignore", RuntimeWarning)
        table = anova_lm(fit, typ=2)
    terms = tuple(_TERM.sub(r"\1", str(term)) for term in table.index)
    total_ss = float(np.sum((response - response.mean()) ** 2))
    sum_sq = table["sum_sq"].to_numpy(dtype=float)
    main_ss = sum(ss for term, ss in zip(terms, sum_sq) if term in factors)
    share = main_ss / total_ss if total_ss > 0 else float("nan")
    return AnovaResult(terms=terms, sum_sq=sum_sq, df=table["df"].to_numpy(dtype=float),
                       f_value=table["F"].to_numpy(dtype=float),
                       p_value=table["PR(>F)"].to_numpy(dtype=float),
                       total_ss=total_ss, main_share=float(share))


def main_effect_share(design, responses, interactions=True):
    """Main-effect share of variance for each response of a design.

    ``design`` is a :class:`motoflex_ros.study.factorial.Design`; ``responses`` maps a name
    (e.g. "weave_low") to an array (runs,). Returns {name: share}.
    """
    return {name: anova(design.coded, values, design.factors, interactions).main_share
            for name, values in responses.items()}
