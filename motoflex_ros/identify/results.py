"""Identified lumped stiffness models of one component from its bench readings.

Static model: l, beta, b (eqs. 1-7) of the mean pose in the hold phase, k by eq. (8), c = gamma
k. Torsion and bending models: l, beta, b as the mean over the peaks of the harmonic tests at
the first torsion / bending eigenfrequency, k by eq. (8) with F_st, y_qst of the static test and
the harmonic arm b, J and c by eqs. (10)-(11) with omega_n, zeta of the mode's eigenvalue
(eq. 9). k_t, k_b by eq. (12). Every value carries a 95 % interval from the measurement scatter
(:mod:`motoflex_ros.identify.uncertainty`); NaN where the scatter is unknown (a single sample or
a single fitted window), null in JSON.
"""
from dataclasses import dataclass

import numpy as np

from motoflex_ros.errors import ProtocolError
from motoflex_ros.identify.axis_model import AxisModel
from motoflex_ros.identify.decay import match_pole
from motoflex_ros.identify.peaks import axis_of_pose, unwrap_axis, wrap_axis
from motoflex_ros.identify.principal import MOMENT_TESTS, identify_principal
from motoflex_ros.identify.stiffness import modal_damping, modal_inertia, static_damping
from motoflex_ros.identify.uncertainty import LEVEL, interval, propagate
from motoflex_ros.lumped_stiffness.axis import axis_stiffness
from motoflex_ros.lumped_stiffness.decomposition import decompose_stiffness, split_problem

__all__ = ["ComponentIdentification", "identify_component", "static_model", "mode_model",
           "harmonic_axis", "split_model", "check_positive_k", "MEASURED_KEY", "ResultsFile",
           "results_source", "MODEL_TESTS", "RESULT_KEYS"]

MODEL_TESTS = ("static", "torsion", "bending")
"""Tests the identification needs, by name: eqs. (8)-(12) use the static test and the harmonic
tests named 'torsion' and 'bending'."""
RESULT_KEYS = ("k_t", "k_b", "split_identifiable", "split_problem", "ci", "sweep", "modal",
               "principal")
"""Keys of :meth:`ComponentIdentification.to_dict` besides the tests' own (:data:`MODEL_TESTS`
and the other harmonic tests, by name): no test may be called like one of them."""
MEASURED_KEY = "measured"
"""Key of an identification of measurements (``motoflex identify --measured``) that says what
was measured and found (tests, counts, reference); no test may be called so either."""


class ResultsFile(dict):
    """Identification results ({component: result dict}) that remember where they came from,
    so that an error about a value can name the file (read by
    :func:`motoflex_ros.formats.json_yaml.load_results_file`)."""

    def __init__(self, data, source):
        super().__init__(data)
        self.source = str(source)


def results_source(identified):
    """The file the results were read from, or a generic name for results built in memory."""
    return getattr(identified, "source", "identification results")


@dataclass(frozen=True)
class ComponentIdentification:
    """All results of one component: static, torsion, bending models, k_t, k_b, the sweep,
    other harmonic tests, the modal data (eigenvalue and free decay) and the principal hinges
    (a PrincipalIdentification, identified or not)."""

    name: str
    static: AxisModel
    torsion: AxisModel
    bending: AxisModel
    split: AxisModel
    sweep: tuple
    modal: dict
    others: dict
    principal: object

    @property
    def split_identifiable(self):
        """Whether eq. (12) gave two positive finite springs k_t, k_b (else they are NaN)."""
        return self.split.info["split_identifiable"]

    def to_dict(self):
        """The JSON/YAML shape the vehicle side reads (k_t, k_b NaN/null and
        ``split_identifiable`` False with ``split_problem`` when eq. 12 has no valid split)."""
        out = {"static": self.static.to_dict(),
               "torsion": self.torsion.to_dict() if self.torsion else None,
               "bending": self.bending.to_dict() if self.bending else None,
               **self.split.values, **self.split.info,
               "ci": {**self.split.ci, "level": LEVEL},
               "sweep": [s.to_dict() for s in self.sweep], "modal": self.modal}
        out.update({name: m.to_dict() for name, m in self.others.items()})
        if self.principal is not None:
            out["principal"] = self.principal.to_dict()
        return out


def _static_values(pose, force, q0, reference_beta):
    axis = axis_of_pose(pose, q0)
    beta, b = unwrap_axis(axis.beta, axis.b, reference_beta)
    return np.array([axis.l, beta, b, axis_stiffness(force, pose[1], b)])


def _pose_steps(pose):
    scale_q = max(np.abs(pose[:3]).max(), 1e-12)
    scale_r = max(np.abs(pose[3:]).max(), 1e-15)
    return np.r_[np.full(3, 1e-6 * scale_q), np.full(3, 1e-6 * scale_r)]


def static_model(reading, q0, stiffness=None):
    """Static model (eqs. 1-8, c = gamma k) with intervals; also returns cov of (l, beta, b, k).

    ``stiffness`` (optional): ``f(pose, axis, b) -> k`` [N m/rad] in place of eq. (8) (e.g. a
    load through a lever, :mod:`motoflex_ros.bench.load_tests`); ``axis`` the pose's
    DeformationAxis, ``b`` its arm as unwrapped here.
    """
    beta0 = axis_of_pose(reading.pose, q0).beta
    if stiffness is None:
        func = lambda p: _static_values(p, reading.force, q0, beta0)  # noqa: E731
    else:
        def func(p):
            axis = axis_of_pose(p, q0)
            beta, b = unwrap_axis(axis.beta, axis.b, beta0)
            return np.array([axis.l, beta, b, stiffness(p, axis, b)])
    values, cov = propagate(func, reading.pose, reading.cov, _pose_steps(reading.pose))
    names = ("l", "beta", "b", "k")
    ci = {n: interval(v, cov[i, i]) for i, (n, v) in enumerate(zip(names, values))}
    values = dict(zip(names, map(float, values)))
    values["beta"], values["b"] = wrap_axis(values["beta"], values["b"])
    values["c"] = static_damping(values["k"])
    ci["c"] = [static_damping(x) for x in ci["k"]]
    return AxisModel(values, ci, {"n_samples": reading.n_samples}), cov


def harmonic_axis(reading):
    """(l, beta, b) of a harmonic reading: values, covariance, intervals, counts."""
    mean, cov = reading.mean()
    mean = mean.copy()
    mean[1], mean[2] = wrap_axis(mean[1], mean[2])
    dof = reading.n_windows - 1  # 0 for a single window: the interval is undefined (NaN)
    ci = {n: interval(mean[i], cov[i, i], dof) for i, n in enumerate(("l", "beta", "b"))}
    info = {"n_peaks": reading.n_peaks, "n_samples": reading.n_samples,
            "settled": reading.settled}
    return dict(zip(("l", "beta", "b"), map(float, mean))), cov, ci, info


def mode_model(reading, static_reading, omega_n, zeta, omega_var=0.0, zeta_var=0.0):
    """Torsion or bending model: axis from the peaks, k by eq. (8), J, c by eqs. (10)-(11).

    omega_n [rad/s] and zeta [-] of the mode; with their variances (measured, e.g. from a free
    decay) the intervals of J and c carry them too (linear propagation: J = k / omega_n^2,
    c = 2 zeta k / omega_n), otherwise (an eigenvalue of the model) only the one of k.
    Returns the AxisModel and the covariance of (l, beta, b).
    """
    values, cov, ci, info = harmonic_axis(reading)
    force, y_st = static_reading.force, static_reading.pose[1]
    x = np.array([values["b"], y_st])
    k, var = propagate(lambda v: np.array([axis_stiffness(force, v[1], v[0])]), x,
                       np.diag([cov[2, 2], static_reading.cov[1, 1]]),
                       1e-6 * np.abs(x))
    k = float(k[0])
    inertia = modal_inertia(k, omega_n)
    values.update(k=k, J=inertia, c=modal_damping(zeta, inertia, omega_n),
                  f_hz=float(reading.frequency_hz))
    ci["k"] = interval(k, var[0, 0])
    if omega_var == 0.0 and zeta_var == 0.0:
        ci["J"] = [modal_inertia(v, omega_n) for v in ci["k"]]
        ci["c"] = [modal_damping(zeta, modal_inertia(v, omega_n), omega_n) for v in ci["k"]]
    else:
        rel_k, rel_w = var[0, 0] / k**2, omega_var / omega_n**2
        rel_z = zeta_var / zeta**2 if zeta else np.nan
        ci["J"] = interval(inertia, inertia**2 * (rel_k + 4.0 * rel_w))
        ci["c"] = interval(values["c"], values["c"]**2 * (rel_z + rel_k + rel_w))
    return AxisModel(values, ci, info), cov


def _mode_model(reading, static_reading, mode):
    """Torsion or bending model of a mode of the component's model (eigenvalue, eq. 9)."""
    return mode_model(reading, static_reading, mode.omega_n, mode.zeta)


def split_model(static, static_cov, torsion, torsion_cov, bending, bending_cov):
    """k_t, k_b by eq. (12) with intervals; inputs (k, beta, b, beta_t, b_t, beta_b, b_b).

    A split that is not two positive finite springs (:func:`split_problem`) is reported as not
    identifiable: k_t, k_b and their intervals NaN, info ``split_identifiable`` False and
    ``split_problem`` the reason.
    """
    x = np.array([static["k"], static["beta"], static["b"], torsion["beta"], torsion["b"],
                  bending["beta"], bending["b"]])
    cov = np.zeros((7, 7))
    order = [3, 1, 2]
    cov[:3, :3] = static_cov[np.ix_(order, order)]
    cov[3:5, 3:5] = torsion_cov[1:, 1:]
    cov[5:, 5:] = bending_cov[1:, 1:]

    def split(v):
        s = decompose_stiffness(*v)
        return np.array([s.k_t, s.k_b])

    values, out_cov = propagate(split, x, cov, 1e-7 * np.maximum(np.abs(x), 1e-3))
    problem = split_problem(float(values[0]), float(values[1]))
    if problem:
        values, out_cov = np.full(2, np.nan), np.full((2, 2), np.nan)
    ci = {n: interval(values[i], out_cov[i, i]) for i, n in enumerate(("k_t", "k_b"))}
    return AxisModel({"k_t": float(values[0]), "k_b": float(values[1])}, ci,
                     {"split_identifiable": problem is None, "split_problem": problem})


def _decay_interval(pole):
    """95 % intervals of omega_n_decay [rad/s] and zeta_decay [-] (residual bootstrap of the
    free decay, :mod:`motoflex_ros.identify.decay`); NaN when undefined (pole not found again
    in half of the replicas, or not found at all)."""
    nan = [float("nan")] * 2
    return {"omega_n_decay": list(pole.omega_n_ci) if pole else nan,
            "zeta_decay": list(pole.zeta_ci) if pole else nan, "level": LEVEL,
            "n_bootstrap": pole.n_bootstrap if pole else 0,
            "n_bootstrap_found": pole.n_found if pole else 0}


def _modal(modes, decay):
    out = {}
    for label in ("torsion", "bending"):
        mode = modes.first(label)
        pole = match_pole(list(decay.poles), mode.omega_n) if decay else None
        out[label] = {"f_hz": mode.f_hz, "omega_n": mode.omega_n, "zeta": mode.zeta,
                      "omega_n_decay": pole.omega_n if pole else None,
                      "zeta_decay": pole.zeta if pole else None,
                      "ci": _decay_interval(pole)}
    out["n_samples_decay"] = decay.n_samples if decay else 0
    return out


def check_positive_k(name, test, model):
    """ProtocolError unless the model's k (eq. 8) is a positive finite stiffness [N m/rad]."""
    k, bounds = model["k"], model.ci["k"]
    if not (np.isfinite(k) and k > 0.0):
        raise ProtocolError(
            f"{name}: the {test} model gives k = {k:.4g} N m/rad (95 % interval "
            f"[{bounds[0]:.4g}, {bounds[1]:.4g}]), not a positive stiffness (eq. 8): the "
            f"measured deflection is lost in the sensor noise; lower sensor.noise_m (--noise) "
            f"or raise the load")


def identify_component(name, readings, modes, q0, carried=None):
    """ComponentIdentification from the readings of a campaign (by test name) and the modes.

    ``carried``: the CarriedInertia whose metric gives the principal hinges
    (:mod:`motoflex_ros.identify.principal`); without it, or without the moment tests, the
    result says why they are not identified.

    ProtocolError when a test is missing, has too few peaks, or gives a k (eq. 8) that is not
    positive (a deflection lost in the sensor noise is no identification result).
    """
    missing = [t for t in MODEL_TESTS if t not in readings]
    if missing:
        raise ProtocolError(f"{name}: the campaign has no {', '.join(missing)} test; eqs. "
                            f"(8)-(12) need the static test and harmonic tests named 'torsion' "
                            f"and 'bending'")
    empty = [t for t in ("torsion", "bending") if readings[t].n_peaks < 2]
    if empty:
        raise ProtocolError(f"{name}: fewer than 2 peaks read in {', '.join(empty)}; "
                            f"raise harmonic.max_periods")
    static, static_cov = static_model(readings["static"], q0)
    check_positive_k(name, "static", static)
    models = {}
    for label in ("torsion", "bending"):
        models[label] = _mode_model(readings[label], readings["static"], modes.first(label))
        check_positive_k(name, label, models[label][0])
    split = split_model(static.values, static_cov, models["torsion"][0].values,
                        models["torsion"][1], models["bending"][0].values, models["bending"][1])
    sweep, others = [], {}
    for test, r in readings.items():
        if getattr(r, "n_peaks", 1) == 0 or test in MOMENT_TESTS:
            continue
        if getattr(r, "kind", None) == "sweep":
            values, _, ci, info = harmonic_axis(r)
            sweep.append(AxisModel({"f_hz": float(r.frequency_hz), **values}, ci, info))
        elif getattr(r, "kind", None) == "harmonic" and test not in models:
            values, _, ci, info = harmonic_axis(r)
            others[test] = AxisModel({"f_hz": float(r.frequency_hz), **values}, ci, info)
    return ComponentIdentification(name, static, models["torsion"][0], models["bending"][0],
                                   split, tuple(sweep), _modal(modes, readings.get("decay")),
                                   others, identify_principal(readings, q0, carried))
