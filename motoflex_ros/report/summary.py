"""The report's opening section: what was tested, how the run ended, what came out.

Which motorcycle and components; the run's outcome (status.json, or the outcome the campaign
hands over when it writes the report before status.json); the identified stiffness k against
the finite-element model's own static k (components.json) and against Table 2, with the reason
for the k_t/k_b gap; and the stability verdict of the identified motorcycle (eig.json: the
least-damped weave and wobble over the sweep, eq. 13's s1). Every number is a traceable
:class:`~.tables.Cell`; a part without its data says so.
"""
import numpy as np

from motoflex_ros.launcher.status import STATUS_FILE, read_status
from motoflex_ros.report.html import Missing, Note
from motoflex_ros.report.tables import Cell, Table, diff_cell, json_cell, paper_cell
from motoflex_ros.structures.paper_tables import COMPONENTS, paper_table2_stiffness
from motoflex_ros.study.verdict import stability_verdict
from motoflex_ros.units import ms_to_kmh
from motoflex_ros.vehicle.variants import variant_label

__all__ = ["summary_parts", "K_SPLIT_REASON", "run_outcome_text"]

K_SPLIT_REASON = (
    "k_t and k_b differ from Table 2 even where k agrees, and systematically so: eq. 12b "
    "splits k along the torsion and bending axes identified on our components (their l and "
    "\u03b2), which differ from the paper's components' axes, so the split differs too.")


def run_outcome_text(folder, outcome=None):
    """(text, source) of how the run ended: ``outcome`` (a status dict handed over by the
    campaign) or the folder's status.json; 'not recorded' with the reason otherwise."""
    status = outcome if outcome is not None else read_status(folder)
    if status is None:
        return f"not recorded (no {STATUS_FILE})", None
    text = str(status.get("status"))
    if status.get("reason"):
        text += f" ({status['reason']})"
    source = status.get("source", STATUS_FILE)
    if status.get("time_utc"):
        source += f", {status['time_utc']}"
    return text, source


def _components_text(data, files):
    components = data.get("components", {})
    names = [c for c in COMPONENTS if c in components] or list(data.get("identify", {}))
    parts = []
    for c in names:
        info = components.get(c, {})
        size = (f" ({info['dofs']} DOFs, {info['modes']} modes kept)"
                if {"dofs", "modes"} <= info.keys() else "")
        parts.append(c.replace("_", " ") + size)
    return ", ".join(parts) or "none recorded"


def _motorcycle_text(data, files):
    eig = data.get("eig")
    if eig is None:
        return "no stability sweep in this run folder (eig.json)"
    vehicle = eig.get("vehicle", "touring")
    if "variant" not in eig:
        return f"the {vehicle} motorcycle (model not recorded in {files.get('eig', 'eig.json')})"
    label = variant_label(eig["variant"], eig["components"])
    return (f"the {vehicle} motorcycle, {label}, built from this run's identified values "
            f"({files.get('identify', 'identification.json')})")


def _stiffness_table(identify, components, files):
    paper = paper_table2_stiffness()
    file = files.get("identify", "identify.json")
    rows = []
    for c in COMPONENTS:
        if c not in identify:
            continue
        ours = json_cell(identify, file, c, "static", "k")
        fe = (json_cell(components, "components.json", c, "k_static")
              if c in components and "k_static" in components[c] else Cell("-"))
        vs_fe = (diff_cell(ours, fe, f"summary/{c}/k_vs_fe") if fe.value is not None
                 else Cell("-"))
        cells = [Cell(c), ours, fe, vs_fe]
        ref = paper_cell(paper[c]["k"], f"table2/{c}/k")
        cells += [ref, diff_cell(ours, ref, f"summary/{c}/k")]
        for name in ("k_t", "k_b"):
            value = json_cell(identify, file, c, name)
            cells += [value, diff_cell(value, paper_cell(paper[c][name], f"table2/{c}/{name}"),
                                       f"summary/{c}/{name}")]
        rows.append(tuple(cells))
    header = ("component", "k identified", "k FE model (static)", "identified vs FE",
              "k Table 2", "vs Table 2", "k_t identified", "vs Table 2", "k_b identified",
              "vs Table 2")
    return Table("summary-stiffness", "Identified stiffness [N m/rad] against the "
                 "finite-element model's own and the paper's Table 2", header, tuple(rows),
                 "k: stiffness about the static deformation axis (eq. 8); the FE model's k is "
                 "the same quantity computed directly on the clamped finite-element model "
                 f"(components.json), the check that the bench identifies the structure it "
                 f"tests. {K_SPLIT_REASON}")


def _modes_of(eig):
    speeds = ms_to_kmh(eig["speeds_mps"])
    modes = {m: np.array([complex(np.nan, np.nan) if z is None else complex(*z) for z in v])
             for m, v in eig.get("modes", {}).items()}
    return speeds, modes


def _stability(eig, file):
    speeds, modes = _modes_of(eig)
    verdict = stability_verdict(speeds, modes)
    if not verdict:
        return [Missing("Stability verdict", f"{file} tracks neither weave nor wobble")]
    rows = []
    for name, v in verdict.items():
        real = json_cell(eig, file, "modes", name, v.index, 0)
        rows.append((Cell(name), real, Cell(f"{v.speed_kmh:.0f}", v.speed_kmh),
                     Cell(f"{v.frequency_hz:.2f}", v.frequency_hz),
                     Cell("stable" if v.stable else "UNSTABLE at " + ", ".join(
                         f"{s:.0f}" for s in v.unstable_kmh) + " km/h",
                          flagged=not v.stable)))
    low, high = float(np.min(speeds)), float(np.max(speeds))
    stable = all(v.stable for v in verdict.values())
    text = (f"Verdict: {'stable' if stable else 'NOT stable'} over {low:.0f}-{high:.0f} km/h: "
            + "; ".join(f"{n} least damped at {v.speed_kmh:.0f} km/h "
                        f"(Re = {v.real:.3g} 1/s, {v.frequency_hz:.2f} Hz)"
                        for n, v in verdict.items()) + ".")
    table = Table("summary-stability", "Stability of the identified motorcycle "
                  f"({low:.0f}-{high:.0f} km/h)",
                  ("mode", "least-damped real part [1/s]", "at speed [km/h]",
                   "frequency there [Hz]", "over the sweep"), tuple(rows),
                  "The largest real part of each mode over the sweep (eq. 13's s1 over the "
                  "whole range); a mode is stable where its real part is negative.")
    return [Note(text, "summary-verdict"), table]


def summary_parts(folder, data, files, outcome=None):
    """The parts of the summary section (Notes, Tables, Missing)."""
    status, source = run_outcome_text(folder, outcome)
    parts = [Note(f"Run {folder.name}: {status}" + (f" ({source})." if source else "."),
                  "summary-status"),
             Note(f"Motorcycle: {_motorcycle_text(data, files)}. Components: "
                  f"{_components_text(data, files)}.", "summary-motorcycle")]
    stability = [Missing("Stability verdict", "no eig.json in the run folder")]
    if "eig" in data:
        try:
            stability = _stability(data["eig"], files.get("eig", "eig.json"))
        except (KeyError, IndexError, TypeError, ValueError) as exc:
            stability = [Missing("Stability verdict", f"eig.json incomplete ({exc})")]
    parts += stability[:1]      # the verdict in words right under the run's outcome
    if "identify" in data:
        parts.append(_stiffness_table(data["identify"], data.get("components", {}), files))
    else:
        parts.append(Missing("Identified stiffness", "no identification in the run folder"))
    return parts + stability[1:]
