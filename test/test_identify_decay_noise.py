"""Free decay with the default 5 um sensor noise (issue 4: "omega_n and zeta from the decay match
the reduced model's eigenvalue within 1 %"), for both the first torsion and the first bending
mode, and the 95 % residual-bootstrap interval of omega_n_decay and zeta_decay against the same
eigenvalues (eq. 9, the clamped reduced model's state matrix: independent of the decay).

The structure's motion does not depend on the sensor: it is simulated once per component and the
sensor and identifier stages are replayed over it with several seeds, as a bag replay would."""
import io
from functools import cache

import numpy as np
import pytest
from deviations import known_deviation

from motoflex_ros.bench.actuator import LoadActuator
from motoflex_ros.bench.offline_campaign import (
    measure_motion,
    only_tests,
    run_campaign,
    setup_campaign,
    with_sensor,
)
from motoflex_ros.config import MOTORCYCLE_COMPONENTS
from motoflex_ros.formats.component_file import load_component
from motoflex_ros.identify.decay import match_pole

SEEDS = 12
LABELS = ("torsion", "bending")

# Why the 1 % cannot be met with one lateral release and 5 um noise (docs/known-deviations.md;
# the numbers measured on the shipped components, 40 seeds):
WEAK_MODE = {
    "frame": known_deviation(
        "decay-weak-mode", "frame: bending mode 1.3e-4 m beside torsion's 2.5e-3 m, zeta +-2.1 %"),
    "swingarm": known_deviation(
        "decay-weak-mode", "swingarm: torsion mode 2.7e-5 m (noise), 2.5 % from a local mode"),
}


@cache
def decay_motion(component):
    """The decay-only setup, its load samples and the true loaded-end motion (no noise)."""
    setup = only_tests(setup_campaign(load_component(component)), ("decay",))
    exact = run_campaign(with_sensor(setup, noise_m=0.0, resolution_m=0.0), trace=True)
    samples = list(iter(LoadActuator(setup.plan).next_sample, None))
    return setup, samples, exact.trace["motion"]


def replay_decay(component, seed):
    """DecayReading of the component's decay measured by the default (5 um) sensor."""
    setup, samples, motions = decay_motion(component)
    return measure_motion(setup, samples, motions, seed)["decay"]


def _marks(component):
    if component in WEAK_MODE:
        return [WEAK_MODE[component]]
    return []


@pytest.mark.parametrize("component", [pytest.param(c, marks=_marks(c))
                                       for c in MOTORCYCLE_COMPONENTS])
def test_free_decay_both_modes_with_noise_within_one_percent_of_eigenvalue(component):
    setup = decay_motion(component)[0]
    assert setup.protocol.sensor.noise_m == pytest.approx(5e-6)
    for seed in range(3):
        poles = list(replay_decay(component, seed).poles)
        for label in LABELS:
            mode = setup.modes.first(label)
            pole = match_pole(poles, mode.omega_n)
            assert pole is not None, (label, seed)
            assert pole.omega_n == pytest.approx(mode.omega_n, rel=0.01), (label, seed)
            assert pole.zeta == pytest.approx(mode.zeta, rel=0.01), (label, seed)


# modes whose decay interval is defined (the pole found again in most bootstrap replicas)
DEFINED = {"frame": LABELS, "front_assembly": LABELS, "swingarm": ("bending",)}


@pytest.mark.parametrize("component", MOTORCYCLE_COMPONENTS)
def test_decay_interval_covers_eigenvalue(component):
    """The 95 % intervals cover the eigenvalue's omega_n and zeta in >= 10 of 12 seeds (a 95 %
    interval misses 3 or more times in 12 with probability 2 %); the swingarm's first torsion
    mode, below the noise (WEAK_MODE), gets an undefined interval in most seeds instead of a
    narrow wrong one."""
    setup = decay_motion(component)[0]
    hits = {(label, key): 0 for label in LABELS for key in ("omega_n", "zeta")}
    undefined = dict.fromkeys(LABELS, 0)
    for seed in range(SEEDS):
        poles = list(replay_decay(component, seed).poles)
        for label in LABELS:
            mode = setup.modes.first(label)
            pole = match_pole(poles, mode.omega_n)
            if pole is None or not np.isfinite(pole.zeta_ci[0]):
                undefined[label] += 1
                continue
            assert pole.n_found >= pole.n_bootstrap / 2 > 0
            for key, ci in (("omega_n", pole.omega_n_ci), ("zeta", pole.zeta_ci)):
                hits[label, key] += ci[0] <= getattr(mode, key) <= ci[1]
    for label in LABELS:
        if label in DEFINED[component]:
            assert undefined[label] == 0, (label, undefined)
            for key in ("omega_n", "zeta"):
                assert hits[label, key] >= SEEDS - 2, (label, key, hits)
        else:
            assert undefined[label] >= SEEDS - 2, (label, undefined)


def test_decay_interval_in_results_and_table():
    """The modal results carry the intervals under 'ci' (as the other identified values) and
    the identify table prints them; an undefined interval is 'n/a'."""
    from motoflex_ros.formats.json_yaml import to_jsonable
    from motoflex_ros.identify.results import _modal
    setup = decay_motion("swingarm")[0]
    modal = to_jsonable(_modal(setup.modes, replay_decay("swingarm", 0)))
    bending = modal["bending"]
    lo, hi = bending["ci"]["zeta_decay"]
    assert lo < bending["zeta_decay"] < hi and bending["ci"]["level"] == 0.95
    assert f"[{lo:.4g}, {hi:.4g}]" in _table_text(modal)
    lo, hi = bending["ci"]["omega_n_decay"]
    assert lo < bending["omega_n_decay"] < hi
    assert f"[{lo:.6g}, {hi:.6g}]" in _table_text(modal) and "n/a" in _table_text(modal)
    assert bending["ci"]["n_bootstrap_found"] <= bending["ci"]["n_bootstrap"]


def _table_text(modal):
    from motoflex_ros.cli.identify import _modal_table
    out = io.StringIO()
    _modal_table({"swingarm": {"modal": modal}}, out)
    return out.getvalue()


@pytest.mark.parametrize("component", MOTORCYCLE_COMPONENTS)
def test_decay_sampling_leaves_no_excited_mode_aliased_roundtrip(component):
    """The decay's rate puts every mode swinging more than DECAY_ALIAS_SHARE of the largest
    below the Nyquist rate (or samples at the sensor's maximum). The shares the planner uses
    (modal coordinates of the static preload) equal those fitted to the simulated decay itself
    (least-squares residues of the eigenvalues' exponentials at the loaded end; the simulator
    joins the preload sample to the first free one by a first-order hold, a release spread
    over one period dt, which scales residue i by (1 - exp(-lambda_i dt)) / (lambda_i dt))."""
    from motoflex_ros.bench.plan import DECAY_ALIAS_SHARE, decay_swing_shares
    setup, _, motions = decay_motion(component)
    plan = setup.plan.test("decay")
    reduced = setup.reduced
    lam = np.array([m.eigenvalue for m in setup.modes.modes])
    dt = 1.0 / plan.rate_hz
    t = np.arange(1, len(motions)) * dt   # sample 0 holds the preload; free from sample 1 on
    basis = np.exp(np.outer(t, np.r_[lam, lam.conj()]))
    residues = np.linalg.lstsq(basis, motions[1:].astype(complex), rcond=None)[0][:len(lam)]
    residues /= ((1 - np.exp(-lam * dt)) / (lam * dt))[:, None]
    length = np.linalg.norm(reduced.q0)
    swing = np.maximum(np.linalg.norm(np.abs(residues[:, :3]), axis=1),
                       length * np.linalg.norm(np.abs(residues[:, 3:]), axis=1))
    fitted = swing / swing.max()
    planned = decay_swing_shares(reduced, plan.amplitude_n)
    visible = planned > 1e-3
    np.testing.assert_allclose(fitted[visible], planned[visible], rtol=1e-6)
    excited = reduced.frequencies_hz[planned > DECAY_ALIAS_SHARE]
    assert (excited.max() < plan.rate_hz / 2
            or plan.rate_hz == setup.protocol.sensor.max_rate_hz), (excited, plan.rate_hz)
