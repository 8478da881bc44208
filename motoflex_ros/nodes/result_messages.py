"""The identification's and the vehicle's results as ROS messages, and back.

Identified models as diagnostic_msgs/DiagnosticStatus (one per test, KeyValue pairs with exact
``repr`` floats) and as std_msgs/Float64MultiArray series a plot panel draws; the vehicle's
tracked modes over speed likewise.
"""
import ast
import json
import math

import numpy as np
from diagnostic_msgs.msg import DiagnosticStatus, KeyValue
from std_msgs.msg import Float64MultiArray, MultiArrayDimension

from motoflex_ros.identify.results import MODEL_TESTS
from motoflex_ros.units import ms_to_kmh

__all__ = ["identification_statuses", "results_from_statuses", "series_msg",
           "IDENTIFIED_UNITS", "identified_series", "mode_statuses",
           "mode_series"]


def _key_values(values):
    out = []
    for key, value in values.items():
        if isinstance(value, dict):
            out += [KeyValue(key=f"{key}.{k}", value=kv.value)
                    for kv in _key_values(value) for k in [kv.key]]
        else:
            out.append(KeyValue(key=str(key), value=repr(_plain(value))))
    return out


def _plain(value):
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, (list, tuple, np.ndarray)):
        return [_plain(v) for v in value]
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items()}
    return value


def identification_statuses(component, result_dict):
    """diagnostic_msgs/DiagnosticStatus list, one per test/model of a component's result dict
    (``ComponentIdentification.to_dict``): name '<component>/<test>', values as KeyValue with
    dotted keys and ``repr`` values (exact floats; None for NaN, an undefined value). The
    split status is WARN with the reason when eq. (12) gave no identifiable k_t, k_b, the
    principal status when the principal hinges are not identified.
    """
    statuses, top = [], {}
    for test, values in result_dict.items():
        if isinstance(values, dict) and test != "ci":
            statuses.append(_status(f"{component}/{test}", values))
        elif isinstance(values, list):
            statuses += [_status(f"{component}/{test}_{i:02d}", v) for i, v in enumerate(values)]
        else:
            top[test] = values
    split = _status(f"{component}/split", top)
    if top.get("split_identifiable") is False:  # eq. (12) gave no usable k_t, k_b
        split.level, split.message = DiagnosticStatus.WARN, str(top.get("split_problem"))
    statuses.insert(0, split)
    principal = result_dict.get("principal")
    if isinstance(principal, dict) and not principal.get("identified"):  # with the reason
        status = next(s for s in statuses if s.name == f"{component}/principal")
        status.level, status.message = DiagnosticStatus.WARN, str(principal.get("problem"))
    return statuses


def _status(name, values):
    return DiagnosticStatus(level=DiagnosticStatus.OK, name=name, message="identified",
                            hardware_id="motoflex_ros", values=_key_values(values))


def results_from_statuses(statuses):
    """Identify-format dict {component: {...}} rebuilt from DiagnosticStatus messages made by
    :func:`identification_statuses` (dotted keys nested again, 'split' values at the top,
    'sweep_NN' statuses back into the 'sweep' list).
    """
    out = {}
    for status in statuses:
        component, test = status.name.split("/", 1)
        values = {}
        for kv in status.values:
            _set_dotted(values, kv.key, ast.literal_eval(kv.value))
        comp = out.setdefault(component, {})
        if test == "split":
            comp.update(values)
        elif test.startswith("sweep_") and test[6:].isdigit():
            comp.setdefault("sweep", []).append(values)
        else:
            comp[test] = values
    return out


def _set_dotted(tree, key, value):
    *parents, leaf = key.split(".")
    for name in parents:
        tree = tree.setdefault(name, {})
    tree[leaf] = value


def mode_statuses(speeds_mps, modes):
    """DiagnosticStatus per tracked mode (weave, wobble, capsize): speeds_kmh, real [1/s],
    frequency_hz (JSON lists; null where the mode is not found)."""
    statuses = []
    for name, values in modes.items():
        values = np.asarray(values, complex)
        ok = np.isfinite(values)
        real = [float(v.real) if f else None for v, f in zip(values, ok)]
        freq = [float(v.imag / (2 * math.pi)) if f else None for v, f in zip(values, ok)]
        statuses.append(DiagnosticStatus(
            level=DiagnosticStatus.OK, name=f"vehicle/{name}", message="eigenvalue over speed",
            hardware_id="motoflex_ros", values=[
                KeyValue(key="speeds_kmh", value=json.dumps(ms_to_kmh(speeds_mps).tolist())),
                KeyValue(key="real", value=json.dumps(real)),
                KeyValue(key="frequency_hz", value=json.dumps(freq))]))
    return statuses


def series_msg(values, label):
    """std_msgs/Float64MultiArray of ``values`` (NaN where None) along one dimension named
    ``label`` (what the elements are, with units): a plot panel draws it against its index or
    against another such array (Foxglove: x axis 'path')."""
    data = [math.nan if v is None else float(v) for v in values]
    msg = Float64MultiArray(data=data)
    msg.layout.dim = [MultiArrayDimension(label=label, size=len(data), stride=len(data))]
    return msg


IDENTIFIED_UNITS = {"k": "N m/rad", "l": "m", "beta": "rad"}


def identified_series(result_dict):
    """{quantity: Float64MultiArray} of a component's result dict: k [N m/rad], l [m] and
    beta [rad] of the static, torsion and bending models, in that order."""
    return {q: series_msg([result_dict.get(m, {}).get(q) for m in MODEL_TESTS],
                          f"{q} [{unit}] of the models {', '.join(MODEL_TESTS)}")
            for q, unit in IDENTIFIED_UNITS.items()}


def mode_series(speeds_mps, modes):
    """{name: Float64MultiArray}: 'speed_kmh' and per tracked mode '<mode>/frequency_hz' and
    '<mode>/real_part' [1/s] over those speeds (NaN where the mode is not found): the same
    numbers as :func:`mode_statuses`, as arrays a plot panel draws against speed."""
    out = {"speed_kmh": series_msg(ms_to_kmh(speeds_mps).tolist(), "speed [km/h]")}
    for name, values in modes.items():
        values = np.asarray(values, complex)
        ok = np.isfinite(values)
        out[f"{name}/frequency_hz"] = series_msg(
            [v.imag / (2 * math.pi) if f else None for v, f in zip(values, ok)],
            f"{name} frequency [Hz] at each speed of /vehicle/modes/speed_kmh")
        out[f"{name}/real_part"] = series_msg(
            [v.real if f else None for v, f in zip(values, ok)],
            f"{name} real part [1/s] at each speed of /vehicle/modes/speed_kmh")
    return out
