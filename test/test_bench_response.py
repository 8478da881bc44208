"""Exact discretisation of the clamped component against closed-form oscillator responses."""
from types import SimpleNamespace

import numpy as np
import pytest

from motoflex_ros.bench.actuator import LoadSample
from motoflex_ros.bench.response import ComponentSimulator, harmonic_peak_motion
from motoflex_ros.identify.peaks import fit_sine

MASS, STIFFNESS, ZETA = 2.0, 8.0e4, 0.02
OMEGA = np.sqrt(STIFFNESS / MASS)
DAMPING = 2 * ZETA * OMEGA * MASS
OMEGA_D = OMEGA * np.sqrt(1 - ZETA**2)


def oscillator():
    """Six uncoupled oscillators; F_y drives the second one (index 1) only."""
    eye = np.eye(6)
    return SimpleNamespace(M=MASS * eye, K=STIFFNESS * eye, C=DAMPING * eye,
                           end_dofs=np.arange(6), q0=np.array([1.0, 0.0, 0.0]))


def run(simulator, forces, dt, kind="static", frequency=0.0):
    out = []
    for j, force in enumerate(forces):
        sample = LoadSample(j, j * dt, dt, force, "t", kind, "x", frequency, j == 0)
        out.append(simulator.step(sample)[1])
    return np.array(out)


def test_first_order_hold_ramp_analytic():
    """M x'' + c x' + k x = r t from rest: x = r/k (t - c/k) + transient (exact for a ramp)."""
    rate, dt = 3.0e4, 1e-3
    t = np.arange(400) * dt
    x = run(ComponentSimulator(oscillator()), rate * t, dt)
    a = rate * DAMPING / STIFFNESS**2
    b = (ZETA * OMEGA * a - rate / STIFFNESS) / OMEGA_D
    exact = (rate / STIFFNESS * (t - DAMPING / STIFFNESS)
             + np.exp(-ZETA * OMEGA * t) * (a * np.cos(OMEGA_D * t) + b * np.sin(OMEGA_D * t)))
    assert np.max(np.abs(x - exact)) < 1e-11 * np.max(np.abs(exact))


@pytest.mark.parametrize("ratio", [0.3, 1.0, 2.2])
def test_harmonic_hold_sine_from_rest_analytic(ratio):
    """F0 sin(W t) from rest: steady state X sin(W t - phi) plus the free transient."""
    f0, w = 10.0, ratio * OMEGA
    dt = 2 * np.pi / w / 8            # 8 samples per period
    t = np.arange(600) * dt
    x = run(ComponentSimulator(oscillator()), f0 * np.sin(w * t), dt, "harmonic",
            w / (2 * np.pi))
    amp = f0 / np.hypot(STIFFNESS - MASS * w**2, DAMPING * w)
    phi = np.arctan2(DAMPING * w, STIFFNESS - MASS * w**2)
    a = amp * np.sin(phi)
    b = (ZETA * OMEGA * a - amp * w * np.cos(phi)) / OMEGA_D
    exact = (amp * np.sin(w * t - phi)
             + np.exp(-ZETA * OMEGA * t) * (a * np.cos(OMEGA_D * t) + b * np.sin(OMEGA_D * t)))
    assert np.max(np.abs(x - exact)) < 1e-10 * amp


def test_first_order_hold_on_sine_aliases_analytic():
    """Why the harmonic tests use the harmonic hold: the piecewise-linear interpolant of a sine
    sampled N times per period is sum_m sinc^2((1 + m N)/N) sin((1 + m N) w t); each line is
    filtered by H and, sampled, lands back on w. Steady sampled amplitude = |sum_m ...|."""
    f0, w, n = 10.0, 0.3 * OMEGA, 8
    dt = 2 * np.pi / w / n
    t = np.arange(4000) * dt
    x = run(ComponentSimulator(oscillator()), f0 * np.sin(w * t), dt, "static")
    c, a, s = fit_sine(t[-800:], np.column_stack([x[-800:]] * 6), w)

    def h(om):
        return 1.0 / (STIFFNESS - MASS * om**2 + 1j * DAMPING * om)

    lines = 1 + n * np.arange(-200, 201)
    sampled = abs(np.sum(np.sinc(lines / n) ** 2 * h(lines * w))) * f0
    assert np.hypot(a[0], s[0]) == pytest.approx(sampled, rel=1e-6)
    assert abs(sampled / (f0 * abs(h(w))) - 1) > 0.05   # a 5.8 % amplitude error at N = 8


def test_steady_state_matches_frequency_response_roundtrip():
    """Time stepping of the tube until steady = the frequency-domain peak pose."""
    from motoflex_ros.formats.component_file import load_component
    reduced = load_component("tube").clamped_reduced()
    freq = 40.0
    w, dt = 2 * np.pi * freq, 1 / (8 * freq)
    sim = ComponentSimulator(reduced)
    t = np.arange(8 * 400) * dt
    motions = []
    for j, tj in enumerate(t):
        sample = LoadSample(j, tj, dt, 50.0 * np.sin(w * tj), "h", "harmonic", "x", freq, j == 0)
        motions.append(sim.step(sample).copy())
    c, a, s = fit_sine(t[-80:], np.array(motions[-80:]), w)
    phase = np.arctan2(s[1], a[1])
    peak = c + a * np.cos(phase) + s * np.sin(phase)
    reference = harmonic_peak_motion(reduced, freq, 50.0)
    assert np.allclose(peak, reference, rtol=0, atol=1e-6 * np.abs(reference).max())
