"""The clamped reduced component re-run on a bag's recorded load history: its exact shapes.

The physics the rerun recording draws on the bench (record/ only writes what this returns).

The component_simulator node steps the clamped reduced model M x'' + C x' + K x = f F_y(t)
under every commanded load sample with :class:`motoflex_ros.bench.response.ComponentSimulator`
(exact discretisation: first-order hold, harmonic hold for harmonic and sweep samples; each
test from rest, a decay test from static equilibrium under its preload). Here the same core
stepper runs on the samples recorded in the bag, so the state at every sample is the
simulator's own and the deformed beam drawn from it moves as the bench did: near resonance the
motion is about 1/(2 zeta) times the quasi-static K^-1 f and has the resonant mode's shape.

A sample is the k-th phase label on /bench/<c>/phase (std_msgs/String, JSON of
:class:`~motoflex_ros.bench.actuator.LoadSample`) with the k-th load on /bench/<c>/load, paired
by order as the nodes pair them; the force is the load's amplitude along the test's unit wrench
(F_y, or the moment tests' torque). A bag without phase labels (or
whose labels do not match the loads' stamps) is replayed from the load stamps alone: one test
from rest, first-order hold between the stamps (exact for a piecewise-linear load).
"""
import json
from dataclasses import dataclass

import numpy as np

from motoflex_ros.bench.actuator import LATERAL_WRENCH, LoadSample, wrench_amplitude
from motoflex_ros.bench.response import ComponentSimulator
from motoflex_ros.units import NS_PER_S

__all__ = ["ReplayedLoads", "recorded_samples", "replayed_displacements"]



@dataclass(frozen=True)
class ReplayedLoads:
    """Load samples to replay and where they came from: ``labelled`` (the phase labels) or
    not (load stamps only, first-order hold from rest)."""

    samples: tuple
    labelled: bool


def _labelled(phases, loads):
    """LoadSamples from phase labels (JSON) paired by order with (t_ns, load); or None."""
    labels = [d for d in (json.loads(p) for p in phases) if "end_ns" not in d]
    if not labels or len(labels) != len(loads):
        return None
    samples = []
    for label, (t_ns, load) in zip(labels, loads):
        if int(round(label["t"] * NS_PER_S)) != t_ns:
            return None
        force = (float(load) if np.ndim(load) == 0
                 else wrench_amplitude(label.get("wrench", LATERAL_WRENCH), load))
        samples.append(LoadSample.from_dict({**label, "force": force}))
    return tuple(samples)


def _from_stamps(loads):
    """LoadSamples of one test from rest, first-order hold between the load stamps."""
    times = np.array([t_ns for t_ns, _ in loads], float) / NS_PER_S
    steps = np.diff(times, prepend=times[0])
    forces = [float(load) if np.ndim(load) == 0 else float(load[1]) for _, load in loads]
    return tuple(LoadSample(k, float(t), float(dt), force, "recorded", "static", "", 0.0, k == 0)
                 for k, (t, dt, force) in enumerate(zip(times, steps, forces)))


def recorded_samples(phases, loads):
    """The load samples of a component's bench run as recorded.

    Parameters
    ----------
    phases : sequence of str
        Data of the /bench/<c>/phase messages in recording order (may be empty).
    loads : sequence of (int, float or (6,))
        (header stamp [ns], F_y [N] or the wrench [N, N m]) of the /bench/<c>/load messages in
        recording order.

    Returns
    -------
    ReplayedLoads

    """
    samples = _labelled(phases, loads)
    if samples is not None:
        return ReplayedLoads(samples, True)
    return ReplayedLoads(_from_stamps(loads), False)


def replayed_displacements(reduced, samples, picks):
    """Node translations (len(picks), n_nodes, 3) [m] of the time response at samples ``picks``.

    ``reduced`` is the clamped ReducedComponent the component simulator integrates; ``samples``
    the LoadSamples of :func:`recorded_samples`; ``picks`` ascending sample indices. The state
    is stepped through every sample (the response depends on the whole history).
    """
    simulator = ComponentSimulator(reduced)
    wanted = {int(k): j for j, k in enumerate(picks)}
    out = np.zeros((len(wanted), len(reduced.transform) // 6, 3))
    for k, sample in enumerate(samples[:max(wanted, default=-1) + 1]):
        simulator.step(sample)
        if k in wanted:
            out[wanted[k]] = reduced.node_displacements(simulator.state[:reduced.n])[:, :3]
    return out
