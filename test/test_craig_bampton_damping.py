"""Modal damping ratio per mode (issue 3): a scalar or one ratio per mode of the clamped reduced
model, from the API or the component file's ``damping_ratio`` key.

Analytic: with C = M Phi diag(2 zeta_i omega_i) Phi^T M (classical damping) each mode keeps its
undamped shape and has the eigenvalue lambda_i = -zeta_i omega_i +/- j omega_i sqrt(1 -
zeta_i^2), so zeta_i = -Re(lambda_i) / |lambda_i| and |lambda_i| = omega_i of the undamped
reduced model (computed here by scipy's eig of the first-order form, not by the code's eigh)."""
import numpy as np
import pytest
import scipy.linalg as sla
import yaml

from motoflex_ros.errors import ConfigError, ModelError
from motoflex_ros.formats.component_file import load_component
from motoflex_ros.structures.clamped import eigenspaces, modal_damping_matrix
from motoflex_ros.structures.craig_bampton import checked_damping_ratio

TUBE = {"component": "tube",
        "tube": {"length": 0.6, "outer_diameter": 0.04, "wall_thickness": 0.002,
                 "pitch_deg": 20.0},
        "material": {"E": 2.1e11, "G": 8.1e10, "rho": 7850}, "elements": 20}


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


def _write(tmp_path, **extra):
    path = tmp_path / "tube.yaml"
    path.write_text(yaml.safe_dump({**TUBE, **extra}))
    return path


def test_per_mode_damping_ratio_in_clamped_eigenvalues_analytic():
    component = load_component("front_assembly")
    n = len(component.clamped_reduced().frequencies_hz)
    ratios = np.linspace(0.002, 0.08, n)
    reduced = component.clamped_reduced(zeta=list(ratios))
    omega, zeta = _damping_of_eigenvalues(reduced)
    assert len(zeta) == n
    np.testing.assert_allclose(zeta, ratios, rtol=1e-8)
    np.testing.assert_allclose(omega, 2 * np.pi * reduced.frequencies_hz, rtol=1e-8)


def _ratios_per_eigenspace(reduced):
    """One ratio per eigenspace of the clamped model (0.003, 0.006, ...), spread over its modes.

    The tube is axisymmetric: its bending modes come in pairs of equal frequency, and the order
    of the two inside a pair depends on the BLAS kernel (issue 13: swapped with
    OPENBLAS_CORETYPE=Prescott), so a ratio is given per eigenspace, never per index."""
    groups = eigenspaces(2 * np.pi * reduced.frequencies_hz)
    assert any(len(g) > 1 for g in groups), "the tube should have degenerate pairs"
    ratios = np.zeros(len(reduced.frequencies_hz))
    for j, group in enumerate(groups):
        ratios[group] = round(0.003 * (j + 1), 6)
    return [float(r) for r in ratios]


def test_damping_ratio_key_roundtrip(tmp_path):
    """A list in the file gives each eigenspace its ratio; a number gives all modes one;
    without the key the default is 1 %. Compared as sorted (omega, zeta) pairs, which does not
    depend on the order of degenerate modes (equal frequencies carry equal ratios)."""
    default = load_component(str(_write(tmp_path))).clamped_reduced(f_max_hz=5000.0)
    np.testing.assert_allclose(_damping_of_eigenvalues(default)[1], 0.01, rtol=1e-8)
    ratios = _ratios_per_eigenspace(default)
    listed = load_component(str(_write(tmp_path, damping_ratio=ratios)))
    omega, zeta = _damping_of_eigenvalues(listed.clamped_reduced(f_max_hz=5000.0))
    np.testing.assert_allclose(omega, 2 * np.pi * default.frequencies_hz, rtol=1e-8)
    np.testing.assert_allclose(zeta, ratios, rtol=1e-8)
    scalar = load_component(str(_write(tmp_path, damping_ratio=0.035)))
    np.testing.assert_allclose(
        _damping_of_eigenvalues(scalar.clamped_reduced(f_max_hz=5000.0))[1], 0.035, rtol=1e-8)


def test_different_ratios_inside_a_degenerate_pair_are_refused(tmp_path):
    """Two ratios for one eigenspace would make the damping matrix depend on the basis the
    eigensolver returned: refused, naming the file, the key and the modes."""
    default = load_component(str(_write(tmp_path))).clamped_reduced(f_max_hz=5000.0)
    pair = next(g for g in eigenspaces(2 * np.pi * default.frequencies_hz) if len(g) > 1)
    ratios = [0.01] * len(default.frequencies_hz)
    ratios[pair[1]] = 0.02
    with pytest.raises(ConfigError) as err:
        load_component(str(_write(tmp_path, damping_ratio=ratios))).clamped_reduced(
            f_max_hz=5000.0)
    message = str(err.value)
    assert "tube.yaml" in message and "damping_ratio" in message
    assert f"modes {pair[0] + 1}, {pair[1] + 1}" in message


def test_modal_damping_does_not_depend_on_the_basis_of_an_eigenspace():
    """Rotating the basis of a degenerate pair (what another BLAS kernel may return) leaves
    C = M Phi diag(2 zeta omega) Phi^T M unchanged when the pair has one ratio."""
    rng = np.random.default_rng(3)
    q, _ = np.linalg.qr(rng.normal(size=(4, 4)))
    mass = np.diag([2.0, 2.0, 1.0, 3.0])
    omega2 = np.array([4.0, 4.0, 9.0, 25.0])            # modes 1 and 2 degenerate
    phi = q / np.sqrt(np.diag(mass))[:, None]            # M^-1/2 Q: M-orthonormal
    stiffness = mass @ phi @ np.diag(omega2) @ phi.T @ mass
    zeta = [0.02, 0.02, 0.05, 0.01]
    got = modal_damping_matrix(mass, stiffness, zeta)
    angle = 0.7
    rot = np.eye(4)
    rot[:2, :2] = [[np.cos(angle), -np.sin(angle)], [np.sin(angle), np.cos(angle)]]
    other = phi @ rot
    want = (mass @ other) @ np.diag(2 * np.array(zeta) * np.sqrt(omega2)) @ (mass @ other).T
    np.testing.assert_allclose(got, want, rtol=1e-10, atol=1e-12)


@pytest.mark.parametrize("value", [1.0, -0.01, float("nan"), "high", [], [0.01, 1.5], {"a": 1}])
def test_bad_damping_ratio_names_key(tmp_path, value):
    with pytest.raises(ConfigError) as err:
        load_component(str(_write(tmp_path, damping_ratio=value)))
    assert "damping_ratio" in str(err.value) and "tube.yaml" in str(err.value)


def test_damping_ratio_list_of_wrong_length_names_key_and_count(tmp_path):
    component = load_component(str(_write(tmp_path, damping_ratio=[0.01, 0.02])))
    with pytest.raises(ConfigError) as err:
        component.clamped_reduced()
    assert "damping_ratio" in str(err.value) and "2 values" in str(err.value)
    assert "6 modes" in str(err.value)  # the tube keeps no mode below 600 Hz: 6 end DOFs


@pytest.mark.parametrize("value", [1.0, -0.1, [], [[0.01]], float("inf")])
def test_checked_damping_ratio_refuses(value):
    with pytest.raises(ModelError):
        checked_damping_ratio(value)
