"""``motoflex components``: build and reduce the clamped components, compare with the paper.

Prints, per component (default: frame, front_assembly, swingarm), the DOF count, the retained
fixed-interface modes, the first torsion and bending frequencies and the static stiffness k
about the static deformation axis (eqs. 1-8), beside Table 1 and Table 2 of Passigato et al.
(2023) with the relative difference. The frequencies are the clamped reduced (Craig-Bampton)
model's; the full clamped model's stand beside them, and a warning is printed when the reduced
model keeps no fixed-interface mode or is more than 0.5 % off. --json prints {name:
{f_torsion_hz, f_bending_hz, k_static, dofs, modes, ..., f_torsion_full_hz,
f_bending_full_hz, frequency_model, warnings}}; --plot DIR writes one PNG per component;
--export DIR writes each component's Craig-Bampton model as a superelement (component:
superelement) that the bench and the vehicle take like the component itself.
"""
import sys
from pathlib import Path

from motoflex_ros.cli.output import emit_json, print_table, progress_bar

__all__ = ["register", "run", "FREQUENCY_MODEL"]

FREQUENCY_MODEL = {"f_torsion_hz": "clamped reduced (Craig-Bampton) model",
                   "f_bending_hz": "clamped reduced (Craig-Bampton) model",
                   "f_torsion_full_hz": "full clamped finite-element model",
                   "f_bending_full_hz": "full clamped finite-element model"}


def register(subparsers):
    parser = subparsers.add_parser(
        "components", help="build and reduce the clamped components; table against the paper",
        description=__doc__.splitlines()[0])
    parser.add_argument("--component", action="append", metavar="NAME|FILE",
                        help="a shipped component (frame, front_assembly, swingarm, tube) or a "
                             "YAML file; repeatable (default: the three motorcycle components)")
    parser.add_argument("--json", action="store_true", help="machine-readable output")
    parser.add_argument("--plot", metavar="DIR", help="write a PNG per component into DIR")
    parser.add_argument("--bodies", action="store_true",
                        help="also list each component's flexible bodies as the paper's Table "
                             "A.1 does (FE DOFs, reduced modes+boundary DOFs) and what their "
                             "assembly gives against the single FE model (--json: key "
                             "'bodies')")
    parser.add_argument("--export", metavar="DIR",
                        help="write each component's Craig-Bampton model as a superelement "
                             "(<name>.yaml, <name>_K.mtx, <name>_M.mtx) into DIR")
    parser.set_defaults(func=run)


def _entry(summary):
    s = summary
    return {"f_torsion_hz": _finite(s.f_torsion_hz), "f_bending_hz": _finite(s.f_bending_hz),
            "k_static": _finite(s.k_static), "dofs": s.dofs, "modes": s.modes,
            "k_t": _finite(s.k_t), "k_b": _finite(s.k_b),
            "static_axis": _axis(summary.static_axis),
            "torsion_axis": _axis(summary.torsion_axis),
            "bending_axis": _axis(summary.bending_axis),
            "f_torsion_full_hz": _finite(s.f_torsion_full_hz),
            "f_bending_full_hz": _finite(s.f_bending_full_hz),
            "frequency_model": FREQUENCY_MODEL, "warnings": list(s.warnings)}


def _axis(axis):
    if axis is None:
        return None
    return {"l": _finite(axis.l), "beta": _finite(axis.beta), "b": _finite(axis.b)}


def _finite(x):
    """JSON has no NaN: a missing value (no such mode, axis at infinity) becomes null."""
    return float(x) if x == x and abs(x) != float("inf") else None


def _rel(ours, paper):
    if paper is None or ours != ours:
        return "-"
    return f"{(ours - paper) / paper:+.1%}"


def _fmt(x, spec):
    return "-" if x is None or x != x else format(x, spec)


def _rows(summaries):
    from motoflex_ros.structures.paper_tables import (
        paper_table1_eigenfrequencies,
        paper_table2_stiffness,
    )
    t1, t2 = paper_table1_eigenfrequencies(), paper_table2_stiffness()
    rows = []
    for s in summaries:
        f_ref, k_ref = t1.get(s.name, {}), t2.get(s.name, {})
        nan = float("nan")
        for label, ours, full, paper, spec in (
                ("f_torsion [Hz]", s.f_torsion_hz, s.f_torsion_full_hz, f_ref.get("torsion"),
                 ".1f"),
                ("f_bending [Hz]", s.f_bending_hz, s.f_bending_full_hz, f_ref.get("bending"),
                 ".1f"),
                ("k [N m/rad]", s.k_static, nan, k_ref.get("k"), ".3g"),
                ("k_t [N m/rad]", s.k_t, nan, k_ref.get("k_t"), ".3g"),
                ("k_b [N m/rad]", s.k_b, nan, k_ref.get("k_b"), ".3g")):
            rows.append([s.name, s.dofs, s.modes, label, _fmt(ours, spec), _fmt(full, spec),
                         _fmt(paper, spec), _rel(ours, paper)])
    return rows


def run(args):
    from motoflex_ros.formats.component_file import load_component
    from motoflex_ros.structures.component_summary import summarize
    from motoflex_ros.structures.paper_tables import COMPONENTS

    names = args.component or list(COMPONENTS)
    components = [load_component(n) for n in names]
    reduced = [c.clamped_reduced() for c in components]
    summaries = [summarize(c, r) for c, r in zip(components, reduced)]
    if args.export:
        from motoflex_ros.formats.superelement_file import export_superelement
        for comp in components:
            export_superelement(comp, args.export)
    if args.plot:
        from motoflex_ros.plots.component_figure import plot_component
        with progress_bar(len(components), "plots", "component") as bar:
            for comp, red in zip(components, reduced):
                plot_component(comp, red, Path(args.plot) / f"{comp.name}.png")
                bar.update(1)
    # flexible bodies of beam components (a mesh or superelement component is one body)
    bodies = {c.name: _bodies_entry(c, s) for c, s in zip(components, summaries)
              if args.bodies and c.kind == "beam"}
    if args.json:
        emit_json({s.name: {**_entry(s), **({"bodies": bodies[s.name]} if s.name in bodies
                                            else {})} for s in summaries})
        return 0
    print_table(["component", "DOFs", "modes", "quantity", "ours (reduced)", "full model",
                 "paper", "difference"], _rows(summaries))
    if bodies:
        print_table(["component", "body", "DOFs FEM", "DOFs after MOR (modes+boundary)"],
                    [[name, b["name"], b["fe_dofs"], b["reduced"]]
                     for name, entry in bodies.items() for b in entry["list"]])
        print_table(["component", "assembled bodies: f_torsion [Hz]", "f_bending [Hz]",
                     "single FE model: f_torsion [Hz]", "f_bending [Hz]"],
                    [[name, _fmt(e["f_torsion_hz"], ".2f"), _fmt(e["f_bending_hz"], ".2f"),
                      _fmt(s.f_torsion_full_hz, ".2f"), _fmt(s.f_bending_full_hz, ".2f")]
                     for (name, e), s in zip(bodies.items(), summaries)])
    for s in summaries:
        for warning in s.warnings:
            sys.stdout.write(f"warning: {warning}\n")
    return 0


def _bodies_entry(component, summary):
    """The component's flexible bodies (paper Table A.1) and the frequencies of their assembly
    nearest the single model's first torsion and bending (``structures.bodies``)."""
    import numpy as np

    from motoflex_ros.structures.bodies import assemble_bodies, reduce_bodies
    bodies = reduce_bodies(component)
    freqs = assemble_bodies(component, bodies).frequencies_hz()

    def nearest(f):
        return _finite(freqs[np.argmin(np.abs(freqs - f))]) if f == f else None
    return {"list": [{"name": b.name, "fe_dofs": b.fe_dofs, "reduced": b.table_a1()}
                     for b in bodies if len(b.nodes) > 1],   # not the nodes held by springs
            "f_torsion_hz": nearest(summary.f_torsion_full_hz),
            "f_bending_hz": nearest(summary.f_bending_full_hz)}
