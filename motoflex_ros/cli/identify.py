"""``motoflex identify``: the bench campaign offline (no ROS), per component.

Static test, harmonic tests at the first torsion and bending frequencies, the sweep and the
modal test (Passigato et al. 2023, Sect. 4.2); prints a table or, with --json, the results
{component: {"static", "torsion", "bending", "k_t", "k_b", "sweep", ...}} (angles rad, lengths
m, stiffness N m/rad), optionally writes them to a YAML/JSON file and the Figs. 5-7 plots.
"""
import math
import sys
from pathlib import Path

from motoflex_ros.cli.inputs import noise_argument, seed_argument
from motoflex_ros.cli.output import (
    add_force_option,
    check_new_file,
    emit_json,
    print_table,
    progress_bar,
)
from motoflex_ros.config import MOTORCYCLE_COMPONENTS
from motoflex_ros.results_file import write_results

__all__ = ["register", "run", "format_interval", "DEFAULT_COMPONENTS"]

DEFAULT_COMPONENTS = MOTORCYCLE_COMPONENTS


def register(subparsers):
    """Add the ``identify`` verb."""
    p = subparsers.add_parser("identify", help="identify lumped stiffness models on the bench",
                              description="Run the bench campaign offline (no ROS) per "
                                          "component: static, harmonic at the first torsion "
                                          "and bending frequencies, sweep, modal; identify "
                                          "l, beta, b, k, c, J and k_t, k_b (eqs. 1-12).")
    p.add_argument("--component", action="append", metavar="NAME|FILE",
                   help="component (shipped name or YAML file); repeatable; default: frame, "
                        "front_assembly, swingarm")
    p.add_argument("--protocol", metavar="FILE",
                   help="protocol YAML (default: the component's shipped protocol)")
    p.add_argument("--noise", type=noise_argument, metavar="SIGMA",
                   help="sensor noise standard deviation [m], in [0, 1e-3] (overrides the "
                        "protocol)")
    p.add_argument("--seed", type=seed_argument, default=0,
                   help="seed of the sensor noise, a whole number >= 0 (default 0)")
    p.add_argument("--out", metavar="FILE", help="write the results (.yaml/.yml or .json); "
                                                 "an existing file only with --force")
    add_force_option(p)
    p.add_argument("--json", action="store_true", help="print the results as JSON only")
    p.add_argument("--plot", metavar="DIR", help="write the Figs. 5-7 axis plots to DIR")
    p.set_defaults(func=run)


def format_interval(bounds, spec=".4g"):
    """'[lo, hi]' of a 95 % interval, or 'n/a' when it is undefined (None/NaN: one sample)."""
    if bounds is None or any(v is None or not math.isfinite(v) for v in bounds):
        return "n/a"
    return f"[{bounds[0]:{spec}}, {bounds[1]:{spec}}]"


def _number(value, spec=".4g"):
    return "n/a" if value is None or not math.isfinite(value) else f"{value:{spec}}"


def _table(results, stream=None):
    stream = stream or sys.stdout
    rows = []
    for name, comp in results.items():
        for test in ("static", "torsion", "bending"):
            r = comp[test]
            rows.append([name, test, f"{r['l']:.4f}", f"{r['beta']:.4f}", f"{r['b']:.4f}",
                         _number(r["k"]), format_interval(r["ci"].get("k")),
                         f"{r.get('f_hz', 0.0):.2f}"])
        for key in ("k_t", "k_b"):
            rows.append([name, f"{key} (eq. 12)", "", "", "", _number(comp[key]),
                         format_interval(comp["ci"].get(key)), ""])
    print_table(["component", "test", "l [m]", "beta [rad]", "b [m]", "k [N m/rad]",
                 "k 95 % interval", "f [Hz]"], rows, stream)
    _modal_table(results, stream)
    for name, comp in results.items():
        if comp.get("split_identifiable") is False:
            stream.write(f"warning: {name}: k_t, k_b not identifiable: "
                         f"{comp['split_problem']}\n")


def _modal_table(results, stream):
    """Eigenvalue (eq. 9) beside the free decay's omega_n, zeta and their 95 % intervals."""
    rows = []
    for name, comp in results.items():
        for label in ("torsion", "bending"):
            m = comp.get("modal", {}).get(label)
            if m is None:
                continue
            ci = m.get("ci", {})
            rows.append([name, label, f"{m['omega_n']:.6g}", _number(m["omega_n_decay"], ".6g"),
                         format_interval(ci.get("omega_n_decay"), ".6g"), f"{m['zeta']:.4g}",
                         _number(m["zeta_decay"]), format_interval(ci.get("zeta_decay"))])
    if rows:
        stream.write("\n")
        print_table(["component", "mode", "omega_n [rad/s]", "decay", "95 % interval",
                     "zeta", "decay", "95 % interval"], rows, stream)


def run(args):
    """Run the campaign of each component; returns the exit code."""
    from motoflex_ros.bench.campaign import identify_components
    components = args.component or list(DEFAULT_COMPONENTS)
    if args.out:
        check_new_file(args.out, args.force)
    with progress_bar(len(components), "bench identification", "component") as bar:
        runs = identify_components(components, args.protocol, args.noise, args.seed,
                                   progress=lambda _name: bar.update(1))
    results = {name: run.identification.to_dict() for name, (_, run) in runs.items()}
    if args.out:
        write_results(args.out, results)
    if args.plot:
        from motoflex_ros.plots.axes import plot_component_axes
        for name, (setup, _) in runs.items():
            plot_component_axes(setup.component, results[name],
                                Path(args.plot) / f"{name}_axes.png")
    if args.json:
        emit_json(results)
    else:
        _table(results)
        sys.stdout.flush()
    return 0
