"""Bench tests that load a component as the vehicle does (beyond the paper).

The paper's static test pulls the loaded end q0 sideways (F_y at q0). On the road the front
assembly and the swingarm are loaded by the tyre's side force at the contact patch, about a
wheel radius lower, and in a wobble the component carries a whole wrench. Two quasi-static
tests here apply such loads: the ramp and hold of the static test (the protocol's ``static``
settings), the loaded end measured by the same marker sensor, the same stages
(:mod:`motoflex_ros.bench.offline_campaign`), only the load is a wrench w1 at q0 per newton of the
commanded force F:

- ``road_load``: F along a unit direction d at a point r, through a rigid lever to q0:
  w1 = (d, (r - q0) x d) (the protocol's ``road_load``: r default the tyre contact point of
  the vehicle's static configuration, d lateral);
- ``vehicle_load``: w1 the direction of the wrench the component carries in a mode of the
  flexible motorcycle (:mod:`motoflex_ros.study.vehicle_load`).

Identification: the axis from the mean pose of the hold by eqs. (1)-(7), as the static test;
the stiffness by eq. (8) with the load's moment about that axis in place of F b,

    k = F m / asin(y_q / b),    m = a . (M1 + (q0 - P) x F1)  [m],

a the axis direction, P the joint (eqs. 3-4), (F1, M1) = w1; for the paper's load (w1 =
(y, 0)) m = b and this is eq. (8). c = gamma k.
"""
from dataclasses import dataclass, replace

import numpy as np

from motoflex_ros.bench.actuator import LoadActuator
from motoflex_ros.bench.offline_campaign import measure_motion
from motoflex_ros.bench.plan import MAX_ROTATION_RAD
from motoflex_ros.bench.response import ComponentSimulator
from motoflex_ros.errors import ModelError, ProtocolError
from motoflex_ros.identify.axis_model import AxisModel
from motoflex_ros.identify.results import static_model

__all__ = ["LoadTestResult", "lever_wrench", "load_arm", "load_test", "load_model",
           "LOAD_TESTS"]

LOAD_TESTS = ("road_load", "vehicle_load")


def lever_wrench(q0, point, direction):
    """Wrench (F, M) at q0 per newton of a force along ``direction`` at ``point`` [m]: the load
    a rigid lever from ``point`` to q0 passes on, (d, (r - q0) x d) [N/N, N m/N]."""
    d = np.asarray(direction, float)
    d = d / np.linalg.norm(d)
    return np.concatenate([d, np.cross(np.asarray(point, float) - np.asarray(q0, float), d)])


def load_arm(axis, q0, wrench):
    """M = a . (M1 + (q0 - P) x F1) [m]: the moment of the unit load about the deformation
    axis (a DeformationAxis in the component frame; P its joint, a its direction)."""
    q0 = np.asarray(q0, float)
    theta = np.arctan2(q0[2], q0[0]) + axis.beta
    a = np.array([np.cos(theta), 0.0, np.sin(theta)])
    joint = np.array([axis.x_j, 0.0, axis.z_j])
    w = np.asarray(wrench, float)
    return float(a @ (w[3:] + np.cross(q0 - joint, w[:3])))


def load_model(reading, q0, wrench):
    """Model (l, beta, b, k, c with intervals) from a static reading under the load ``wrench``
    per newton (module docstring): eqs. (1)-(7) and k = F m / asin(y_q / b)."""
    def stiffness(pose, axis, b):
        return reading.force * load_arm(axis, q0, wrench) / np.arcsin(pose[1] / axis.b)

    return static_model(reading, q0, stiffness)[0]


@dataclass(frozen=True)
class LoadTestResult:
    """A load test: ``name``, the load ``wrench`` at q0 per newton, ``force_n`` [N], the
    identified ``model`` (AxisModel: l, beta, b, k, c) and the measured mean end motion
    (q - q0, theta) [m, rad] of the hold."""

    name: str
    wrench: np.ndarray
    force_n: float
    model: AxisModel
    end_motion: np.ndarray

    def to_dict(self):
        """The model's values with intervals, the load (wrench per newton, force)."""
        return {**self.model.to_dict(), "wrench_per_n": [float(v) for v in self.wrench],
                "force_n": self.force_n}


def load_test(setup, wrench, name, force_n=None, seed=0):
    """Run a quasi-static load test on a CampaignSetup (its reduced model, protocol, sensor).

    ``wrench`` (6,): the load at q0 per newton [N/N, N m/N]; ``force_n`` [N] the commanded
    force (None: the protocol's static force). Returns a LoadTestResult; ProtocolError when
    the deflection is too small or too large to read (k not positive, rotation beyond the
    bench's linear range).
    """

    wrench = np.asarray(wrench, float)
    if wrench.shape != (6,) or not np.all(np.isfinite(wrench)) or not np.any(wrench):
        raise ModelError(f"{setup.name}: a load test needs a finite, non-zero wrench (6,), "
                         f"got {wrench!r}")
    static = setup.plan.test("static")
    force = float(static.amplitude_n if force_n is None else force_n)
    test = replace(static, name=name, amplitude_n=force)
    plan = replace(setup.plan, tests=(test,))
    reduced = setup.reduced
    rotation = np.linalg.norm(reduced.static_end_motion(force * wrench)[3:])
    if rotation > MAX_ROTATION_RAD:
        raise ProtocolError(f"{setup.protocol.source}: key 'road_load.force_n': test '{name}' "
                            f"would turn the loaded end by {rotation:.3g} rad, beyond the "
                            f"bench's linear range ({MAX_ROTATION_RAD} rad); lower the force")
    q0 = np.asarray(reduced.q0, float)
    actuator, simulator = LoadActuator(plan), ComponentSimulator(reduced, wrench)
    samples, motions = [], []
    while (sample := actuator.next_sample()) is not None:
        samples.append(sample)
        motions.append(simulator.step(sample))
    reading = measure_motion(replace(setup, plan=plan), samples, motions, seed)[name]
    model = load_model(reading, q0, wrench)
    if not model.values["k"] > 0:
        raise ProtocolError(f"{setup.protocol.source}: test '{name}' of {setup.name}: k = "
                            f"{model.values['k']:.4g} N m/rad is not positive (the load's "
                            "moment about the identified axis is lost in the sensor noise)")
    return LoadTestResult(name, wrench, force, model, np.asarray(reading.pose, float))
