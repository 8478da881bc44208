"""Sensor noise: 5 micrometres keep the static k and beta within 1 % of the noise-free values,
and the reported 95 % intervals cover the noise-free values in at least 90 % of 50 seeds.

The structure's true motion does not depend on the sensor, so it is simulated once and the
sensor and identifier stages are replayed over its hold phase (the samples the static test
reads) with 50 seeds, as a bag replay would."""
import numpy as np
import pytest

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
from motoflex_ros.identify.results import static_model

REPETITIONS = 50


def replay_static(setup, samples, motions, seed):
    readings = measure_motion(setup, samples, motions, seed)
    return static_model(readings["static"], setup.reduced.q0)[0]


@pytest.mark.parametrize("component", MOTORCYCLE_COMPONENTS)
def test_static_noise_within_one_percent_and_interval_covers(component):
    setup = only_tests(setup_campaign(load_component(component)), ("static",))
    assert setup.protocol.sensor.noise_m == pytest.approx(5e-6)
    exact_setup = with_sensor(setup, noise_m=0.0, resolution_m=0.0)
    exact_run = run_campaign(exact_setup, trace=True)
    exact = static_model(exact_run.readings["static"], setup.reduced.q0)[0]
    actuator = LoadActuator(setup.plan)
    hold = [(s, m) for s, m in zip(iter(actuator.next_sample, None), exact_run.trace["motion"])
            if s.phase == "hold"]
    samples, motions = zip(*hold)
    covered = {"k": 0, "beta": 0}
    for seed in range(REPETITIONS):
        noisy = replay_static(setup, samples, motions, seed)
        for key in covered:
            assert noisy[key] == pytest.approx(exact[key], rel=0.01), (key, seed)
            lo, hi = noisy.ci[key]
            covered[key] += lo <= exact[key] <= hi
    for key, hits in covered.items():
        assert hits >= 0.9 * REPETITIONS, (key, hits)


def test_noisy_interval_width_scales_with_noise():
    """Halving the noise halves the interval (linear propagation of the scatter)."""
    setup = only_tests(setup_campaign(load_component("swingarm")), ("static",))
    widths = []
    for noise in (5e-6, 2.5e-6):
        run = run_campaign(with_sensor(setup, noise_m=noise, resolution_m=0.0), seed=3)
        model = static_model(run.readings["static"], setup.reduced.q0)[0]
        widths.append(np.diff(model.ci["k"])[0])
    assert widths[1] / widths[0] == pytest.approx(0.5, rel=0.15)


@pytest.mark.parametrize("component", MOTORCYCLE_COMPONENTS)
def test_free_decay_with_noise_within_one_percent_of_eigenvalue(component):
    """Release from the preload with the default 5 um sensor: the first torsion/bending mode,
    which dominates the decay, within 1 % of its eigenvalue (eq. 9). (The other one can carry
    a few percent of the decay's amplitude only, e.g. the frame's bending mode 6 %, beside
    aliased higher modes; it is checked without noise in test_identify_campaign.)"""
    from motoflex_ros.identify.decay import match_pole
    setup = only_tests(setup_campaign(load_component(component)), ("decay",))
    first = setup.modes.first_lateral()
    for seed in range(3):
        pole = match_pole(list(run_campaign(setup, seed=seed).readings["decay"].poles),
                          first.omega_n)
        assert pole is not None, seed
        assert pole.omega_n == pytest.approx(first.omega_n, rel=0.01), seed
        assert pole.zeta == pytest.approx(first.zeta, rel=0.01), seed
