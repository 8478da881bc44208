"""The virtual bench's measurements as a real rig would hand them over (issue 17).

:func:`campaign_measurements` runs a component's campaign exactly as
:func:`motoflex_ros.bench.offline_campaign.run_campaign` does (same stages, same order, same sensor
noise for the same seed, so its identification is the virtual identification) and keeps, per
sample, the load and the markers the emulated sensor measured for it (noise and resolution, matched
to their sample by index: a real rig's capture time).
:func:`motoflex_ros.formats.measured_csv.write_measured_csv` writes them in the measured CSV format
and :func:`bench_of` gives the matching bench file, so that ``motoflex identify --measured`` can
identify the virtual bench without its finite-element model.
"""
from dataclasses import dataclass

import numpy as np

from motoflex_ros.bench.offline_campaign import make_stages
from motoflex_ros.identify.results import MODEL_TESTS, identify_component
from motoflex_ros.spatial import rotation_from_vector

__all__ = ["CampaignMeasurements", "campaign_measurements", "bench_of"]


@dataclass(frozen=True)
class CampaignMeasurements:
    """Per sample: time t [s], load F_y [N] (as wrenches (n, 6)), measured markers (n, N, 3)
    [m], test names; the virtual identification of the same run and the component's q0 [m]
    and marker offsets (N, 3) [m], the sensor noise [m] and the carried inertia (or None)."""

    t: np.ndarray
    wrench: np.ndarray
    markers: np.ndarray
    tests: tuple
    identification: object
    q0: np.ndarray
    offsets: np.ndarray
    noise_m: float
    carried: object = None


def campaign_measurements(setup, seed=0):
    """Run the campaign of a CampaignSetup and keep its measurements (module doc)."""
    actuator, simulator, sensor, identifier = make_stages(setup, seed)
    q0 = np.asarray(setup.reduced.q0, float)
    samples, measured = [], {}

    def deliver(measurements):
        for m in measurements:
            measured[m.index] = m.markers
            done = identifier.add_measurement(m)
            if done:
                actuator.end_test(done)

    while (sample := actuator.next_sample()) is not None:
        motion = simulator.step(sample)
        identifier.add_load(sample)
        samples.append(sample)
        deliver(sensor.capture(sample.index, sample.t, q0 + motion[:3],
                               rotation_from_vector(motion[3:])))
    deliver(sensor.flush())
    readings = identifier.readings()
    result = None
    if set(MODEL_TESTS) <= set(readings):
        result = identify_component(setup.name, readings, setup.modes, q0, setup.carried)
    wrench = np.array([s.wrench_vector for s in samples], float).reshape(-1, 6)
    return CampaignMeasurements(np.array([s.t for s in samples]), wrench,
                                np.array([measured[s.index] for s in samples]),
                                tuple(s.test for s in samples), result, q0,
                                np.asarray(setup.protocol.sensor.markers, float),
                                setup.protocol.sensor.noise_m, setup.carried)


def bench_of(name, measurements, markers="offsets", latency_s=0.0):
    """The bench file (a mapping) of CampaignMeasurements: q0, the sensor's noise, the marker
    offsets (``markers='offsets'``) or ``'from_data'`` and the carried inertia if any."""
    out = {"bench": name, "loaded_end": [float(v) for v in measurements.q0],
           "markers": (measurements.offsets.tolist() if markers == "offsets" else markers),
           "sensor": {"noise_m": float(measurements.noise_m), "latency_s": float(latency_s)}}
    if measurements.carried is not None:
        out["carried"] = measurements.carried.bench_key()
    return out
