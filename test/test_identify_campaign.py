"""The bench campaign on the three motorcycle components, and on a solid mesh component (an L
bracket of hexahedra: issue 15), with an exact sensor (no noise, no rounding): harmonic tests
against the static test, the modes and the frequency response; the sweep's migration (Figs.
5-7); the free decay against the eigenvalues (eq. 9)."""
import numpy as np
import pytest

from motoflex_ros.bench.offline_campaign import run_campaign, setup_campaign, with_sensor
from motoflex_ros.bench.response import harmonic_peak_motion
from motoflex_ros.formats.component_file import load_component
from motoflex_ros.identify.decay import match_pole
from motoflex_ros.identify.peaks import axis_of_pose, unwrap_angle

COMPONENTS = ("frame", "front_assembly", "swingarm", "mesh_bracket")


@pytest.fixture(scope="module", params=COMPONENTS)
def exact_campaign(request, tmp_path_factory):
    component = request.param
    if component == "mesh_bracket":
        from motoflex_ros.formats.mesh_examples import write_bracket_component
        component = str(write_bracket_component(tmp_path_factory.mktemp("bracket")))
    setup = with_sensor(setup_campaign(load_component(component)), noise_m=0.0, resolution_m=0.0)
    return setup, run_campaign(setup)


def steady_axis(setup, frequency):
    """Deformation axis of the steady harmonic response at its peak (frequency domain)."""
    motion = harmonic_peak_motion(setup.reduced, frequency)
    return axis_of_pose(motion * 1e-6 / np.abs(motion).max(), setup.reduced.q0)


def test_harmonic_far_below_first_mode_equals_static(exact_campaign):
    setup, run = exact_campaign
    result = run.identification
    slow = result.sweep[0]
    assert slow["f_hz"] <= 0.05 * setup.modes.first_lateral().f_hz
    for key in ("l", "beta", "b"):
        assert slow[key] == pytest.approx(result.static[key], rel=0.01), key


def test_harmonic_tests_match_frequency_response(exact_campaign):
    """Every harmonic and sweep test = the steady state of the frequency response."""
    setup, run = exact_campaign
    length = np.linalg.norm(setup.reduced.q0)
    for reading in run.readings.values():
        if not hasattr(reading, "peaks"):
            continue
        (l, beta, b), _ = reading.mean()
        ref = steady_axis(setup, reading.frequency_hz)
        assert unwrap_angle(beta, ref.beta) == pytest.approx(ref.beta, abs=5e-3), reading.name
        assert b == pytest.approx(ref.b, abs=2e-3 * length), reading.name


def test_harmonic_at_first_eigenfrequency_gives_mode_axis(exact_campaign):
    setup, run = exact_campaign
    first = setup.modes.first_lateral()
    model = getattr(run.identification, first.label)
    assert model["f_hz"] == pytest.approx(first.f_hz, rel=1e-12)
    mode = setup.reduced.mode_axis(first.label)
    length = np.linalg.norm(setup.reduced.q0)
    assert unwrap_angle(model["beta"], mode.beta) == pytest.approx(mode.beta, abs=0.02)
    assert model["b"] == pytest.approx(mode.b, abs=0.02 * length)


def test_sweep_moves_monotonically_from_static_to_first_mode(exact_campaign):
    setup, run = exact_campaign
    result = run.identification
    target = steady_axis(setup, setup.modes.first_lateral().f_hz).beta
    betas = np.array([unwrap_angle(p["beta"], result.static["beta"]) for p in result.sweep])
    target = unwrap_angle(target, result.static["beta"])
    distance = np.abs(betas - target)
    assert np.all(np.diff(distance) < 1e-4), distance
    assert np.all(np.sign(np.diff(betas)) == np.sign(target - betas[0]))


def test_free_decay_matches_eigenvalues(exact_campaign):
    setup, run = exact_campaign
    poles = list(run.readings["decay"].poles)
    for label in ("torsion", "bending"):
        mode = setup.modes.first(label)
        pole = match_pole(poles, mode.omega_n, tolerance=0.01)
        assert pole is not None, label
        assert pole.omega_n == pytest.approx(mode.omega_n, rel=1e-6)
        assert pole.zeta == pytest.approx(mode.zeta, rel=1e-4)


def frequency_domain_split(setup):
    """k, k_t, k_b from the exact static response and the steady harmonic peaks (eqs 8, 12)."""
    from motoflex_ros.lumped_stiffness.decomposition import decompose_stiffness
    static = setup.reduced.static_lateral(setup.protocol.static.force_n)
    t = steady_axis(setup, setup.modes.first("torsion").f_hz)
    b = steady_axis(setup, setup.modes.first("bending").f_hz)
    split = decompose_stiffness(static.k, static.axis.beta, static.axis.b, t.beta, t.b,
                                b.beta, b.b)
    return static.k, split.k_t, split.k_b


def test_stiffness_split_matches_frequency_domain(exact_campaign):
    setup, run = exact_campaign
    k, k_t, k_b = frequency_domain_split(setup)
    result = run.identification
    assert result.static["k"] == pytest.approx(k, rel=1e-4)
    assert result.split["k_t"] == pytest.approx(k_t, rel=0.01)
    assert result.split["k_b"] == pytest.approx(k_b, rel=0.01)
