"""The report's design section: ``motoflex study design --json`` (design.json) as tables.

Beyond the paper (issue 26; docs/design-study.md): the nominal design, the lightest design that
keeps every stability index (eq. 15) at least its floor, and the Pareto front of structural
mass against the smallest stability margin, each number linked to its place in design.json.
"""
from motoflex_ros.report.html import Figure, Note
from motoflex_ros.report.tables import Cell, Table, json_cell
from motoflex_ros.study.stability_index import INDEX_NAMES

__all__ = ["design_parts"]


def _row(design, file, label, *path):
    point = design
    for key in path:
        point = point[key]
    cells = [Cell(label), json_cell(design, file, *path, "mass_kg", spec=".3f")]
    cells += [json_cell(design, file, *path, "indices", n, spec=".4f") for n in INDEX_NAMES]
    if "full_check" in point and point["full_check"] is not None:
        cells.append(json_cell(design, file, *path, "full_check", "max_abs_difference",
                               spec=".1e"))
    else:
        cells.append(Cell("-"))
    return tuple(cells)


def design_parts(design, file="design.json"):
    """Tables and notes of the design section from the study's JSON ``design``."""
    rows = [_row(design, file, "nominal", "nominal")]
    if design.get("lightest_feasible"):
        rows.append(_row(design, file, "lightest feasible", "lightest_feasible"))
    rows += [_row(design, file, f"Pareto {i}", "pareto", i)
             for i in range(len(design.get("pareto", [])))]
    header = ("design", "mass [kg]", *INDEX_NAMES, "full check |diff|")
    parts = [Table("design", "Designs: structural mass of the members and the stability "
                   "indices (eq. 15)", header, tuple(rows),
                   "full check: largest difference of the indices from a full re-reduction "
                   "and linearization of the flexible motorcycle.")]
    if design.get("pareto"):   # matplotlib only when drawn, as report.build's _figures
        from motoflex_ros.plots.design_front import design_front_figure
        from motoflex_ros.report.figures import png_of
        parts.append(Figure("design_front", "Structural mass of the members against the "
                            "smallest stability margin min(s_i - floor_i) (eq. 15): the Pareto "
                            "front, the nominal (square) and the lightest feasible design "
                            "(star)", png_of(design_front_figure(design))))
    if design.get("why_none"):
        parts.append(Note(design["why_none"], "design-why-none"))
    lightest = design.get("lightest_feasible")
    if lightest and lightest.get("files"):
        parts.append(Note("Component files of the lightest feasible design (for motoflex eig "
                          "--use): " + ", ".join(f"{c}: {p}" for c, p in
                                                 lightest["files"].items()), "design-files"))
    return parts
