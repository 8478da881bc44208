"""Build bags/<run>/report.html from the run's JSON sources (see :mod:`.sources`).

Sections whose data does not exist are listed as "not available" with the reason; no number
is ever made up. Progress bars (tqdm, stderr) run over the data sources and the sections.
"""
import time

from motoflex_ros.files import atomic_write_text
from motoflex_ros.launcher.campaign_graph import VEHICLE_COMPONENTS, VEHICLE_VARIANT
from motoflex_ros.progress import progress_bar
from motoflex_ros.report import tables
from motoflex_ros.report.html import Figure, Missing, Note, Section, render
from motoflex_ros.report.provenance_section import provenance_table
from motoflex_ros.report.sources import FIG9_VARIANTS, load_run_data
from motoflex_ros.report.summary import summary_parts
from motoflex_ros.structures.paper_tables import COMPONENTS
from motoflex_ros.vehicle.variants import variant_label

__all__ = ["build_report", "SECTIONS", "REPORT_FILE"]

REPORT_FILE = "report.html"
OPTIONAL_SECTIONS = ("design",)
"""Sections shown only when their data is in the run folder (``motoflex study design --json``
saved as design.json): a run without the study has no design section, not a missing one."""
PAPER = "Passigato et al. 2023"


def _figures():
    from motoflex_ros.report import figures
    return figures


def _components(data, files):
    from motoflex_ros.plots.component_figure import MODE_FRACTION
    components = data["components"]
    parts = [tables.components_table(components), tables.table1(components)]
    for name in COMPONENTS:
        parts.append(Figure(
            f"modes_{name}", f"{name}: first torsion (green, solid) and bending (red, dashed) "
            "modes of the clamped reduced model over the undeformed structure (grey); clamps "
            f"light blue, loaded end orange. Each mass-normalised mode shape is drawn times the "
            f"scale factor in the legend, so that its largest node translation is "
            f"{MODE_FRACTION:.0%} of the component's size.",
            _figures().component_modes_figure(name)))
    return parts


def _identification(data, files):
    identify = data["identify"]
    table2 = tables.table2(identify, files["identify"])
    return [tables.identification_table(identify, files["identify"]), table2]


AXES_CAPTION = (
    "deformation axes in the x-z plane, the figure 'motoflex identify --plot' writes: static "
    "axis blue, torsion axis green (solid) and bending axis red (dashed) from the harmonic tests "
    "at the first torsion and bending eigenfrequencies; thin grey lines are the axes of the "
    "frequency sweep (harmonic tests from 1 Hz to 5 Hz below the first eigenfrequency), shaded "
    "by test frequency on the colour bar, which converge on the static axis as the frequency "
    "falls. l and \u03b2 in the legend as in the identification table.")


def _axes(data, files):
    identify = data["identify"]
    numbers = {"frame": 5, "front_assembly": 6, "swingarm": 7}
    return [Figure(f"fig{numbers[c]}_{c}", f"Fig. {numbers[c]} ({PAPER}), "
                   f"{c.replace('_', ' ')}: {AXES_CAPTION}",
                   _figures().axes_figure(c, identify[c]))
            for c in COMPONENTS]


def _accuracy(data, files):
    accuracy = data["accuracy"]
    return [tables.accuracy_table(accuracy),
            Figure("fig8", f"Fig. 8 ({PAPER}): e_RMS of the lumped models against the flexible "
                   "ones, per component made flexible and for all three; log axis, each bar "
                   "labelled with its value [%]", _figures().fig8_figure(accuracy))]


def _fig9(data, files):
    variants = {v: data[f"fig9_{v}"] for v in FIG9_VARIANTS if f"fig9_{v}" in data}
    if "flexible" not in variants or len(variants) < 2:
        raise KeyError("fig9_flexible and at least one lumped variant")
    return [Figure("fig9", f"Fig. 9 ({PAPER}): front assembly flexible only; weave and wobble "
                   "against speed", _figures().fig9_figure(variants))]


def _sensitivity(data, files):
    sensitivity = data["sensitivity"]
    return [tables.anova_table(sensitivity), tables.pearson_table(sensitivity),
            Figure("fig10", f"Fig. 10 ({PAPER}): Pearson coefficients of weave and wobble "
                   "indices per stiffness", _figures().fig10_figure(sensitivity))]


def _design(data, files):
    from motoflex_ros.report.design_tables import design_parts
    return design_parts(data["design"], files["design"])


def _vehicle(data, files):
    eig = data["eig"]
    vehicle = eig.get("vehicle", "touring")
    if "variant" in eig:
        variant, label = eig["variant"], variant_label(eig["variant"], eig["components"])
        text = (f"The {vehicle} motorcycle identified on this run: the {label}, built from the "
                f"run's identified values ({files['identify']}).")
        if (variant, list(eig["components"])) == (VEHICLE_VARIANT, list(VEHICLE_COMPONENTS)):
            text += " It is the model the campaign's vehicle_simulator runs and prints."
    else:
        variant, label = "unknown", f"model not recorded in {files['eig']}"
        text = f"{files['eig']} does not record which motorcycle model it holds."
    return [Note(text, "vehicle-model"),
            Figure("eig_touring", f"{vehicle.capitalize()} motorcycle, {label}: weave and "
                   "wobble against speed", _figures().fig9_figure({variant: eig}))]


def _whipple(data, files):
    return [tables.whipple_table(data["whipple"])]


# (id, title, needed sources, builder)
SECTIONS = (
    ("components", "Components and their modes (Table 1)", ("components",), _components),
    ("identification", "Identification (Table 2)", ("identify",), _identification),
    ("axes", "Deformation axes (Figs. 5-7)", ("identify",), _axes),
    ("accuracy", "Accuracy of the lumped models (Fig. 8)", ("accuracy",), _accuracy),
    ("fig9", "Front assembly: weave and wobble over speed (Fig. 9)", (), _fig9),
    ("sensitivity", "Sensitivity (Fig. 10)", ("sensitivity",), _sensitivity),
    ("vehicle", "Vehicle stability", ("eig",), _vehicle),
    ("design", "Design for stability at least mass (beyond the paper)", ("design",), _design),
    ("whipple", "Whipple benchmark check", ("whipple",), _whipple),
)


def _section(run_data, spec):
    section_id, title, needs, builder = spec
    absent = [n for n in needs if n not in run_data.data]
    if absent:
        reasons = "; ".join(f"{n}: {run_data.missing.get(n, 'missing')}" for n in absent)
        return Section(section_id, title, (Missing(title, reasons),))
    try:
        return Section(section_id, title, tuple(builder(run_data.data, run_data.files)))
    except (KeyError, IndexError, TypeError, ValueError) as exc:
        missing = "; ".join(f"{k}: {v}" for k, v in run_data.missing.items()
                            if k.startswith(section_id))
        return Section(section_id, title, (Missing(title, missing or f"incomplete data ({exc})"),))


def _sources_table(run_data):
    """Where each JSON source of the report came from (saved, or the verb run now)."""
    rows = tuple((tables.Cell(name), tables.Cell(origin))
                 for name, origin in sorted(run_data.origins.items()))
    return tables.Table("sources", "Data sources of this report", ("source", "origin"), rows)


def build_report(folder, compute=True, progress=True, warning=None, outcome=None):
    """Write ``folder``/report.html (``warning``, e.g. an incomplete run, at the top); returns
    (path, sections).

    The summary comes first, then the sections of :data:`SECTIONS`, then the appendices
    (provenance, data sources, timings). ``outcome``: the run's status dict when the caller
    knows it before status.json exists (``motoflex campaign`` writes the report, then the
    status; a report it cannot finish fails the run and is removed), with a ``source``.
    """
    run_data = load_run_data(folder, compute=compute, progress=progress)
    summary = Section("summary", "Summary",
                      tuple(summary_parts(folder, run_data.data, run_data.files, outcome)))
    sections = [summary]
    bar = progress_bar(SECTIONS, desc="report sections", unit="section", enabled=progress)
    for spec in bar:
        if spec[0] in OPTIONAL_SECTIONS and not all(n in run_data.data for n in spec[2]):
            continue
        bar.set_postfix_str(spec[0])
        start = time.perf_counter()
        sections.append(_section(run_data, spec))
        run_data.timings.append((f"section: {spec[0]}", time.perf_counter() - start))
    sections += [Section("provenance", "Appendix A: provenance",
                         (provenance_table(folder, outcome),)),
                 Section("sources", "Appendix B: data sources", (_sources_table(run_data),)),
                 Section("timings", "Appendix C: timings (for the developers)",
                         (tables.timings_table(run_data),))]
    html = render(f"motoflex_ros run report: {folder.name}", sections, warning)
    path = folder / REPORT_FILE
    atomic_write_text(path, html)
    return path, sections
