"""Tables of the report, built from the verbs' JSON: each number cell knows where it came from.

A :class:`Cell` holding a number from a JSON source carries the source file and the path to the
value inside it (``data-json`` / ``data-path`` in the HTML), so a test can check every number
against the JSON it was made from. Paper values carry ``paper`` and differences ``diff``.
"""
from dataclasses import dataclass

import numpy as np

from motoflex_ros.plots.labels import QUANTITY_LABELS, VARIANT_LABELS
from motoflex_ros.report.published import meijaard2007_eigenvalues
from motoflex_ros.structures.paper_tables import (
    COMPONENTS,
    paper_table1_eigenfrequencies,
    paper_table2_stiffness,
)
from motoflex_ros.study.accuracy import QUANTITIES
from motoflex_ros.study.factorial import FACTORS
from motoflex_ros.study.stability_index import INDEX_NAMES

__all__ = ["Cell", "Table", "components_table", "table1", "table2", "identification_table",
           "whipple_table", "accuracy_table", "anova_table", "pearson_table", "timings_table",
           "percent_difference", "VARIANTS", "DEVIATION_FLAG_PERCENT",
           "TIMING_FLOOR_S", "flagged_count", "SYMBOLS_NOTE", "json_cell", "paper_cell",
           "diff_cell", "ASSUMED_C_NOTE"]

VARIANTS = ("state_of_the_art", "static", "torsion", "bending", "principal")


@dataclass(frozen=True)
class Cell:
    """A table cell: text, and for numbers the value and its origin (kind, file, path)."""

    text: str
    value: float = None
    kind: str = None        # 'json', 'paper', 'diff', 'absdiff', 'provenance' or 'missing'
    file: str = None
    path: str = None
    shown_unit: str = None  # the text shows the value in this unit (beta: 'deg' of rad)
    flagged: bool = False   # a deviation beyond DEVIATION_FLAG_PERCENT


@dataclass(frozen=True)
class Table:
    """A titled table with a header row and rows of :class:`Cell`."""

    id: str
    title: str
    header: tuple
    rows: tuple
    note: str = ""


def _fmt(value, spec=".4g"):
    return "-" if value is None or not np.isfinite(value) else format(value, spec)


def json_cell(data, file, *keys, spec=".4g"):
    """A number of a JSON source shown with the format ``spec``; null (an undefined value: a
    one-sample interval, a split eq. 12 cannot give) is shown as 'n/a' and carries no
    value."""
    value = data
    for key in keys:
        value = value[key]
    path = "/".join(map(str, keys))
    if value is None:
        return Cell("n/a", None, "json", file, path)
    return Cell(_fmt(value, spec), float(value), "json", file, path)


def paper_cell(value, path):
    return Cell(_fmt(value), float(value), "paper", None, path)


DEVIATION_FLAG_PERCENT = 10.0
"""A difference from the paper beyond this [%] is flagged in Tables 1 and 2 (our finite-element
components are not the paper's, so some deviation is expected; beyond 10 % a chassis engineer
would not take the number for the paper's without asking why)."""
FLAG_NOTE = (f"Differences beyond \u00b1{DEVIATION_FLAG_PERCENT:g} % are flagged (\u26a0, "
             "red).")


def percent_difference(ours, paper):
    """(ours - paper) / paper * 100 [%]."""
    return (ours - paper) / paper * 100.0


def diff_cell(ours, paper, path):
    if ours.value is None:
        return Cell("n/a", None, "diff", None, path)
    value = percent_difference(ours.value, paper.value)
    flagged = abs(value) > DEVIATION_FLAG_PERCENT
    return Cell(f"{value:+.1f} %" + (" \u26a0" if flagged else ""), value, "diff", None, path,
                flagged=flagged)


def flagged_count(table):
    """How many cells of ``table`` are flagged deviations."""
    return sum(c.flagged for row in table.rows for c in row)


def components_table(components):
    """The components: model size, clamped modes, first torsion/bending frequencies, k."""
    fields = ("dofs", "modes", "f_torsion_hz", "f_bending_hz", "k_static")
    rows = tuple((Cell(c), *(json_cell(components, "components.json", c, f) for f in fields))
                 for c in COMPONENTS if c in components)
    return Table("components", "Components (clamped finite-element models)",
                 ("component", "DOFs", "modes kept", "f torsion [Hz]", "f bending [Hz]",
                  "k static [N m/rad]"), rows)


def table1(components):
    """Table 1: first torsion and bending eigenfrequencies, ours beside the paper's."""
    paper = paper_table1_eigenfrequencies()
    rows = []
    for c in COMPONENTS:
        for shape in ("torsion", "bending"):
            ours = json_cell(components, "components.json", c, f"f_{shape}_hz")
            ref = paper_cell(paper[c][shape], f"table1/{c}/{shape}")
            rows.append((Cell(c), Cell(shape), ours, ref,
                         diff_cell(ours, ref, f"table1/{c}/{shape}")))
    return _flag_note(Table("table1", "Table 1: first torsion and bending eigenfrequency",
                            ("component", "mode shape", "ours [Hz]", "paper [Hz]",
                             "difference"), tuple(rows)))


def _flag_note(table):
    """``table`` with a note stating the flag threshold and how many cells exceed it."""
    count = flagged_count(table)
    return Table(table.id, table.title, table.header, table.rows,
                 f"{FLAG_NOTE} {count} flagged." + (f" {table.note}" if table.note else ""))


def table2(identify, file="identify.json"):
    """Table 2: k about the static axis and its split k_t, k_b (eq. 12), ours and paper's."""
    paper = paper_table2_stiffness()
    rows = []
    for c in COMPONENTS:
        cells = [Cell(c)]
        for name, keys in (("k", ("static", "k")), ("k_t", ("k_t",)), ("k_b", ("k_b",))):
            ours = json_cell(identify, file, c, *keys)
            ref = paper_cell(paper[c][name], f"table2/{c}/{name}")
            cells += [ours, ref, diff_cell(ours, ref, f"table2/{c}/{name}")]
        rows.append(tuple(cells))
    header = ("component", *(f"{n} {w}" for n in ("k", "k_t", "k_b")
                             for w in ("ours [N m/rad]", "paper [N m/rad]", "difference")))
    return _flag_note(Table("table2", "Table 2: stiffness about the static axis k and about "
                            "the torsion and bending axes (eq. 12)", header, tuple(rows)))


def _k_interval(identify, file, *path):
    """Cells of the 95 % interval of k: 'n/a' where undefined (null), '-' where absent."""
    values = identify
    for key in path:
        values = values[key]
    if "k" not in values.get("ci", {}):
        return (Cell("-"), Cell("-"))
    return tuple(json_cell(identify, file, *path, "ci", "k", i) for i in (0, 1))


def _models(identify, c):
    """(label, key path) of a component's models: static, torsion, bending and, where they
    were identified, the principal hinges (beyond the paper)."""
    out = [(test, (c, test)) for test in ("static", "torsion", "bending")]
    principal = identify[c].get("principal") or {}
    if principal.get("identified"):
        out += [(f"principal {i + 1}", (c, "principal", "hinges", i))
                for i in range(len(principal.get("hinges") or []))]
    return out


def identification_table(identify, file="identify.json"):
    """Identified l, beta, b, k, c (and J, f) per component and test (eqs. 1-11) and the
    principal hinges, with the 95 % interval of k."""
    names = ("l", "beta", "b", "k", "c", "J", "f_hz")
    rows = []
    for c in COMPONENTS:
        for label, path in _models(identify, c):
            values = identify
            for key in path:
                values = values[key]
            rows.append((Cell(c), Cell(label), *(
                _value_cell(identify, file, *path, n) if n in values else Cell("-")
                for n in names), *_k_interval(identify, file, *path)))
    return Table("identification", "Identified lumped stiffness models",
                 ("component", "test", "l [m]", "\u03b2 [deg]", "b [m]", "k [N m/rad]",
                  "c [N m s/rad]", "J [kg m^2]", "f [Hz]", "k 95 % low [N m/rad]",
                  "k 95 % high [N m/rad]"), tuple(rows), f"{SYMBOLS_NOTE} {ASSUMED_C_NOTE}")


ASSUMED_C_NOTE = (
    "c of the static test is assumed, not identified (marked 'assumed'): c = \u03b3 k with "
    "\u03b3 = 0.001 s, the paper's choice for static models (Sect. 5.2.4); the harmonic tests' "
    "c are identified (eqs. 9-11).")


def _value_cell(identify, file, *keys):
    """An identified value's cell (``keys``: its path, the value's name last): beta in
    degrees, the static test's c marked assumed."""
    if keys[-1] == "beta":
        return _degrees(identify, file, *keys)
    cell = json_cell(identify, file, *keys)
    if keys[-2:] == ("static", "c") and cell.value is not None:
        return Cell(f"{cell.text} (assumed)", cell.value, cell.kind, cell.file, cell.path)
    return cell


SYMBOLS_NOTE = (
    "Each test's deformation axis lies in the x-z plane: l [m] is the signed distance from the "
    "origin O to the axis' joint on the line O-q0 (q0: the loaded end; eq. 5), \u03b2 [deg] "
    "the angle from the line O-q0 to the axis (eq. 6; the JSON holds it in rad), b [m] the "
    "lever arm from the axis to q0 (eq. 7), k [N m/rad] and c [N m s/rad] the torsional "
    "stiffness and damping about the axis, J [kg m^2] the inertia of the harmonic test's "
    "fit and f [Hz] its frequency (eqs. 8-11). Principal hinges (beyond the paper): hinges in "
    "series from the bench's 3 x 3 end compliance in the metric of the carried inertia "
    "(static test and two moment tests), c = 0.001 s x k.")


def _degrees(data, file, *keys):
    """A JSON angle [rad] shown in degrees; the cell keeps the JSON value and says so."""
    cell = json_cell(data, file, *keys)
    if cell.value is None:
        return cell
    return Cell(f"{np.degrees(cell.value):.2f}", cell.value, "json", file, cell.path,
                shown_unit="deg")


def _nearest(eigenvalues, target):
    values = np.array([complex(re, im) for re, im in eigenvalues])
    return values[np.argmin(np.abs(values - target))]


def whipple_table(whipple):
    """Whipple benchmark: our eigenvalue nearest to each published one, and |difference|."""
    rows = []
    for i, speed in enumerate(whipple["speeds_mps"]):
        published = meijaard2007_eigenvalues().get(round(float(speed), 6))
        if published is None:
            continue
        for name, ref in published.items():
            ours = _nearest(whipple["eigenvalues"][i], ref)
            index = [complex(*z) for z in whipple["eigenvalues"][i]].index(ours)
            rows.append((Cell(f"{speed:g}"), Cell(name),
                         json_cell(whipple, "whipple.json", "eigenvalues", i, index, 0),
                         json_cell(whipple, "whipple.json", "eigenvalues", i, index, 1),
                         paper_cell(ref.real, f"whipple/{speed:g}/{name}/re"),
                         paper_cell(ref.imag, f"whipple/{speed:g}/{name}/im"),
                         Cell(f"{abs(ours - ref):.2e}", float(abs(ours - ref)), "absdiff")))
    return Table("whipple", "Whipple benchmark check (Meijaard et al. 2007)",
                 ("v [m/s]", "eigenvalue", "ours Re [1/s]", "ours Im [1/s]", "published Re",
                  "published Im", "|difference|"), tuple(rows),
                 "The benchmark asks for agreement to 1e-6 or better.")


def accuracy_table(accuracy):
    """e_RMS% (eq. 18) per case and lumped variant: every variant of the JSON, in its order,
    the same the bars of Fig. 8 show."""
    rows = tuple((Cell(case), Cell(VARIANT_LABELS.get(v, v)),
                  *(json_cell(accuracy, "accuracy.json", case, v, q)
                                         for q in QUANTITIES))
                 for case in (*COMPONENTS, "all") if case in accuracy
                 for v in accuracy[case])
    return Table("accuracy", "e_RMS of lumped against flexible models [%] (Fig. 8)",
                 ("case", "variant", *(f"{QUANTITY_LABELS[q]} [%]" for q in QUANTITIES)), rows,
                 "e_RMS (eq. 18): root-mean-square difference over 40-210 km/h of each lumped "
                 "model's weave and wobble frequency and real part from the flexible model's, "
                 "in % of the flexible model's.")


def anova_table(sensitivity):
    """Share of the index variance explained by main effects (ANOVA, Sect. 4.3)."""
    rows = tuple((Cell(i), json_cell(sensitivity, "sensitivity.json", "anova_main_share", i))
                 for i in INDEX_NAMES)
    return Table("anova", "ANOVA: share of main effects", ("index", "main-effect share"), rows)


def pearson_table(sensitivity):
    """Pearson coefficients (eqs. 16-17) per index and stiffness (the numbers of Fig. 10)."""
    rows = tuple((Cell(i), *(json_cell(sensitivity, "sensitivity.json", "pearson", i, f,
                                       spec="+.3f") for f in FACTORS)) for i in INDEX_NAMES)
    return Table("pearson", "Pearson correlation coefficients (Fig. 10)", ("index", *FACTORS),
                 rows, "Three decimals throughout; +1: a stiffer part damps the mode more.")


TIMING_FLOOR_S = 0.01
"""Report steps faster than this [s] are summed into one row instead of rows of 0.00."""


def timings_table(run_data):
    """Timings: the campaign's (timings.json) and this report's own steps [s]; the report's
    steps under :data:`TIMING_FLOOR_S` are summed into one row."""
    rows = [(Cell(f"campaign: {step}"), json_cell(run_data.campaign_timings, "timings.json", step))
            for step, value in run_data.campaign_timings.items()
            if isinstance(value, (int, float))]
    slow = [(step, s) for step, s in run_data.timings if s >= TIMING_FLOOR_S]
    fast = [s for _, s in run_data.timings if s < TIMING_FLOOR_S]
    rows += [(Cell(f"report: {step}"), Cell(f"{seconds:.2f}", seconds)) for step, seconds in slow]
    if fast:
        rows.append((Cell(f"report: {len(fast)} further steps, each under "
                          f"{TIMING_FLOOR_S:g} s (reading saved JSON, tables)"),
                     Cell(f"{sum(fast):.2g}", sum(fast))))
    return Table("timings", "Timings of the run", ("step", "wall time [s]"), tuple(rows))
