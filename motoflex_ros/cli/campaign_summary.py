"""What ``motoflex campaign`` prints at the end: the identified stiffness against the
finite-element model's own static k and the paper's Table 2 (with why k_t and k_b differ from
it), the identified motorcycle's weave and wobble with the stability verdict, and the same as
JSON (``--json``: the results per component plus ``bag`` and ``stability``).
"""
import numpy as np

from motoflex_ros.cli.output import print_table
from motoflex_ros.report.summary import K_SPLIT_REASON
from motoflex_ros.study.verdict import stability_verdict
from motoflex_ros.vehicle.mode_names import STUDIED_MODES

__all__ = ["fe_static_k", "stiffness_table", "vehicle_table", "stability_json", "json_output",
           "verdict_text"]

TABLE_SPEEDS_KMH = (60.0, 100.0, 150.0, 200.0)


def fe_static_k(components):
    """{name: k [N m/rad]} of the clamped reduced finite-element model itself (eq. 8, the
    static lateral load the bench applies), for the components given by name or YAML file;
    a component without a model is left out."""
    from motoflex_ros.formats.component_file import shipped_model
    out = {}
    for spec in components:
        model = shipped_model(spec)
        if model is not None:
            out[model[0].name] = float(model[1].static_lateral(100.0).k)
    return out


def _percent(value, ref):
    return f"{100.0 * (value / ref - 1.0):+.1f} %" if value is not None and ref else ""


def _number(value):
    return "n/a" if value is None else f"{value:.4g}"


def stiffness_table(results, fe_k, stream=None):
    """Print identified k, k_t, k_b beside the FE model's own k and Table 2, then the reason
    for the k_t/k_b gap."""
    from motoflex_ros.structures.paper_tables import paper_table2_stiffness
    paper = paper_table2_stiffness()
    rows = []
    for name, comp in results.items():
        ref = paper.get(name, {})
        for key, value in (("k", comp["static"]["k"]), ("k_t", comp["k_t"]),
                           ("k_b", comp["k_b"])):
            fe = fe_k.get(name) if key == "k" else None
            target = ref.get(key)
            rows.append([name, key, _number(value), "" if fe is None else f"{fe:.4g}",
                         _percent(value, fe), f"{target:.4g}" if target else "",
                         _percent(value, target)])
    print_table(["component", "stiffness", "identified [N m/rad]", "FE model", "vs FE",
                 "paper Table 2", "vs Table 2"], rows, stream)
    print("FE model: the clamped finite-element model's own static k (eq. 8), which the bench "
          "should find.", file=stream)
    print(K_SPLIT_REASON, file=stream)


def _eigenvalues(mode):
    real = np.array([np.nan if r is None else r for r in mode["real"]], float)
    freq = np.array([np.nan if f is None else f for f in mode["frequency_hz"]], float)
    return real + 2j * np.pi * freq


def _verdict(modes):
    speeds = next(iter(modes.values()))["speeds_kmh"] if modes else []
    return speeds, stability_verdict(speeds, {m: _eigenvalues(v) for m, v in modes.items()})


def verdict_text(modes):
    """One line: stable or not over the sweep, and each mode's least-damped point."""
    speeds, verdict = _verdict(modes)
    if not verdict:
        return "stability: neither weave nor wobble tracked"
    stable = all(v.stable for v in verdict.values())
    return (f"{'stable' if stable else 'NOT stable'} over {min(speeds):.0f}-{max(speeds):.0f} "
            "km/h: " + "; ".join(f"{n} least damped at {v.speed_kmh:.0f} km/h (Re = "
                                 f"{v.real:.3g} 1/s, {v.frequency_hz:.2f} Hz)"
                                 for n, v in verdict.items()))


def vehicle_table(modes, stream=None, speeds_kmh=TABLE_SPEEDS_KMH):
    """Print weave and wobble at a few speeds, then the verdict over the whole sweep."""
    rows = []
    for name in STUDIED_MODES:
        mode = modes.get(name)
        if not mode:
            continue
        for v in speeds_kmh:
            k = min(range(len(mode["speeds_kmh"])), key=lambda i: abs(mode["speeds_kmh"][i] - v))
            freq, real = mode["frequency_hz"][k], mode["real"][k]
            rows.append([name, f"{mode['speeds_kmh'][k]:.0f}",
                         "-" if freq is None else f"{freq:.3f}",
                         "-" if real is None else f"{real:.3f}"])
    print_table(["mode", "speed [km/h]", "frequency [Hz]", "real part [1/s]"], rows, stream)
    print(verdict_text(modes), file=stream)


def stability_json(modes, variant, components):
    """The ``stability`` entry of ``campaign --json``: the model, weave and wobble against
    speed (speeds_kmh, real [1/s], frequency_hz [Hz], null where not found) and each mode's
    verdict (:meth:`~motoflex_ros.study.verdict.ModeVerdict.as_dict`); None without a
    vehicle."""
    if not modes:
        return None
    _, verdict = _verdict(modes)
    return {"model": {"vehicle": "touring", "variant": variant, "components": list(components)},
            "modes": {m: modes[m] for m in STUDIED_MODES if m in modes},
            "verdict": {m: v.as_dict() for m, v in verdict.items()},
            "stable": bool(verdict) and all(v.stable for v in verdict.values())}


def json_output(outcome, variant, components):
    """``campaign --json``: {component: identify-format results} as before, plus ``bag`` (the
    run folder) and ``stability`` (:func:`stability_json`, null without a vehicle)."""
    return {**outcome.results, "bag": str(outcome.bag),
            "stability": stability_json(outcome.vehicle, variant, components)}
