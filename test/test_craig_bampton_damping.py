"""Modal damping ratio per mode (issue 3): a scalar or one ratio per mode of the clamped reduced
model, from the API or the component file's ``damping_ratio`` key.

Analytic: with C = M Phi diag(2 zeta_i omega_i) Phi^T M (classical damping) each mode keeps its
undamped shape and has the eigenvalue lambda_i = -zeta_i omega_i +/- j omega_i sqrt(1 -
zeta_i^2), so zeta_i = -Re(lambda_i) / |lambda_i| and |lambda_i| = omega_i of the undamped
reduced model (computed here by scipy's eig of the first-order form, not by the code's eigh)."""
import numpy as np
import pytest
import scipy.linalg as sla

from motoflex_ros.errors import ModelError
from motoflex_ros.structures.components import load_component
from motoflex_ros.structures.craig_bampton import checked_damping_ratio


def _damping_of_eigenvalues(reduced):
    """(omega_n [rad/s], zeta [-]) of the state matrix's eigenvalues, ascending omega_n."""
    n = reduced.K.shape[0]
    a = np.block([[np.zeros((n, n)), np.eye(n)],
                  [-np.linalg.solve(reduced.M, reduced.K), -np.linalg.solve(reduced.M,
                                                                            reduced.C)]])
    lam = sla.eigvals(a)
    lam = lam[lam.imag > 0]
    lam = lam[np.argsort(np.abs(lam))]
    return np.abs(lam), -lam.real / np.abs(lam)


def test_per_mode_damping_ratio_in_clamped_eigenvalues_analytic():
    component = load_component("front_assembly")
    n = len(component.clamped_reduced().frequencies_hz)
    ratios = np.linspace(0.002, 0.08, n)
    reduced = component.clamped_reduced(zeta=list(ratios))
    omega, zeta = _damping_of_eigenvalues(reduced)
    assert len(zeta) == n
    np.testing.assert_allclose(zeta, ratios, rtol=1e-8)
    np.testing.assert_allclose(omega, 2 * np.pi * reduced.frequencies_hz, rtol=1e-8)


@pytest.mark.parametrize("value", [1.0, -0.1, [], [[0.01]], float("inf")])
def test_checked_damping_ratio_refuses(value):
    with pytest.raises(ModelError):
        checked_damping_ratio(value)
