"""Pearson correlation of stability indices with the factors, eqs. (16)-(17).

Passigato et al. 2023, Sect. 4.3, step 3 (after Doria [25]). The population (1/n) moments of
eq. (17) are used; the paper's "sigma_IF^2" in eq. (17) is the covariance sigma_IF (it enters
eq. (16) unsquared), so rho = sigma_IF / (sigma_I sigma_F) lies in [-1, 1]. A positive value
means that a stiffer part raises the index, i.e. damps the mode more (Sect. 5.3).
"""
import numpy as np

__all__ = ["pearson", "pearson_table"]


def pearson(factors, indices):
    """Eqs. (16)-(17): rho_IF for every index I and factor F.

    Parameters
    ----------
    factors : array (runs, n_factors)
        Factor values of every run (coded or physical: rho does not depend on the scale).
    indices : array (runs, n_indices) or (runs,)
        Index values of every run.

    Returns
    -------
    array (n_indices, n_factors)
        rho_IF [-]; NaN where an index or a factor does not vary.

    Examples
    --------
    An index that rises linearly with the first factor and falls with the second, which are
    uncorrelated: rho = +1, -1 and 0 for a factor orthogonal to both:

    >>> factors = np.array([[-1, -1, 1], [1, -1, -1], [-1, 1, -1], [1, 1, 1]])
    >>> index = 2.0 * factors[:, 0] + 1.0
    >>> (pearson(factors, index) + 0.0).tolist()
    [[1.0, 0.0, 0.0]]
    >>> (pearson(factors, -factors[:, 1]) + 0.0).tolist()
    [[0.0, -1.0, 0.0]]

    """
    f = np.asarray(factors, dtype=float)
    i = np.asarray(indices, dtype=float)
    i = i[:, None] if i.ndim == 1 else i
    n = f.shape[0]
    df = f - f.mean(axis=0)
    di = i - i.mean(axis=0)
    sigma_f = np.sqrt((df**2).sum(axis=0) / n)
    sigma_i = np.sqrt((di**2).sum(axis=0) / n)
    sigma_if = di.T @ df / n
    scale = np.outer(sigma_i, sigma_f)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(scale > 0, sigma_if / scale, np.nan)


def pearson_table(design, indices):
    """rho_IF as {index name: {factor name: rho}} for a design and {name: array (runs,)}."""
    names = list(indices)
    rho = pearson(design.coded, np.column_stack([indices[name] for name in names]))
    return {name: {factor: float(rho[k, j]) for j, factor in enumerate(design.factors)}
            for k, name in enumerate(names)}
