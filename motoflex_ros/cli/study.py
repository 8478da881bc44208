"""``motoflex study``: studies on the lumped motorcycle (Passigato et al. 2023, Sect. 4.3, 5.3).

    motoflex study sensitivity [--levels 2] [--range-rel 0.10] [--scheduler ADDRESS|local]
                               [--identified FILE] [--nominal identified|table2]
                               [--vehicle touring] [--step-kmh 1] [--json] [--plot DIR]
                               [--model lumped|flexible] [--extra-range-kmh LO HI ...]

``sensitivity``: full factorial over the six stiffnesses of the decomposed lumped motorcycle
(k_tf, k_bf, k_ta, k_ba, k_ts, k_bs) at +/- range around the nominal values, weave and wobble
over 40-210 km/h for every run, the stability indices (eqs. 13-15) in 40-100 and 100-210 km/h,
ANOVA main-effect shares and Pearson coefficients (eqs. 16-17). --json prints {"nominal",
"indices": {"weave_low": [...], ...}, "anova_main_share", "pearson"} (null where an index does
not vary). --plot DIR writes the Fig. 10 bar chart and the runs' weave/wobble real parts.
Without --identified the bench identification runs first (motoflex identify); --nominal table2
takes k_t, k_b from the paper's Table 2 instead (axes still from the identification);
--nominal principal runs the factorial on the principal hinges' stiffnesses (the principal
variant; each factor named after the paper's one its axis stands for, :func:`motoflex_ros.study.
motorcycle.principal_study`), with --model flexible its Pearson coefficients beside the flexible
study's.
--model flexible runs the same design on the flexible motorcycle (each factor scales the modal
stiffness of its component's first torsion or bending mode of the clamped model,
:mod:`motoflex_ros.study.flexible_sensitivity`; default 5 km/h steps) and the lumped study on
the same speeds; --json adds "definition", "agreement" ({index: {factor: {"lumped",
"flexible", "difference", "verdict"}}}) and "lumped" (the lumped study's JSON).
--extra-range-kmh LO HI (repeatable, inside 40-210 km/h) adds the indices of that speed range,
named "<mode>_<LO>-<HI>kmh" (e.g. wobble_40-95kmh), to the tables, ANOVA, Pearson and JSON
(beyond the paper: eq. 13 over 40-100 km/h sits at 100 km/h, where the +/-10 % wobble curves
of several factors cross).
"""
import argparse
import sys
from pathlib import Path

import numpy as np

from motoflex_ros.cli.inputs import (
    add_study_inputs,
    component_roles,
    identification_results,
    motorcycle_components,
    study_speeds,
)
from motoflex_ros.cli.options import deprecated
from motoflex_ros.cli.output import emit_json, print_table
from motoflex_ros.cli.study_accuracy import register_accuracy
from motoflex_ros.cli.study_design import register_design
from motoflex_ros.config import MOTORCYCLE_COMPONENTS, resolve_config
from motoflex_ros.errors import ConfigError
from motoflex_ros.vehicle.mode_names import STUDIED_MODES

__all__ = ["register", "run", "SUBCOMMANDS"]

_ARGS = "command line"
_COMPONENTS = MOTORCYCLE_COMPONENTS


def _register_sensitivity(sub):
    p = sub.add_parser("sensitivity", help="2^6 (or 3^6) factorial, ANOVA, Pearson (Fig. 10)",
                       description="Sensitivity of weave and wobble to the six lumped "
                                   "stiffnesses (Passigato et al. 2023, Sect. 5.3).")
    p.add_argument("--levels", type=int, default=2, help="levels per factor (default 2)")
    p.add_argument("--range", type=float, dest="rel_range", help=argparse.SUPPRESS,
                   action=deprecated("--range-rel"), default=argparse.SUPPRESS)
    p.add_argument("--range-rel", type=float, default=0.10, dest="rel_range",
                   help="relative half-range of the stiffnesses (default 0.10)")
    p.add_argument("--scheduler", metavar="ADDRESS",
                   help="run on Dask: a scheduler address (tcp://host:8786) or 'local'")
    add_study_inputs(p)
    p.add_argument("--nominal", choices=("identified", "table2", "principal"),
                   default="identified",
                   help="nominal k_t, k_b: identified (default) or the paper's Table 2; "
                        "principal: the factorial on the principal hinges' stiffnesses (the "
                        "principal variant, beyond the paper)")
    p.add_argument("--step-kmh", type=float, default=None,
                   help="speed step [km/h] (default 1; 5 with --model flexible)")
    p.add_argument("--model", choices=("lumped", "flexible"), default="lumped",
                   help="lumped: the decomposed lumped motorcycle (the paper's); flexible: the "
                        "superelements' modal stiffnesses scaled, with the agreement table")
    p.add_argument("--extra-range-kmh", type=float, nargs=2, action="append", default=[],
                   metavar=("LO", "HI"),
                   help="also index this speed range [km/h] (inside 40-210; repeatable)")
    p.add_argument("--json", action="store_true", help="print JSON only")
    p.add_argument("--plot", metavar="DIR", help="write the Fig. 10 bar chart and curves (PNG)")
    p.set_defaults(func=run_sensitivity_verb)


def extra_ranges(args):
    """The --extra-range-kmh pairs [km/h]; ConfigError unless 40 <= LO < HI <= 210."""
    for low, high in args.extra_range_kmh:
        if not 40.0 <= low < high <= 210.0:
            raise ConfigError(_ARGS, "--extra-range-kmh",
                              f"need 40 <= LO < HI <= 210 km/h, got {low:g} {high:g}")
    return [tuple(pair) for pair in args.extra_range_kmh]


# study kinds: name -> function adding its parser (the accuracy study adds its own here)
SUBCOMMANDS = {"sensitivity": _register_sensitivity, "accuracy": register_accuracy,
               "design": register_design}


def register(subparsers):
    """Add the ``study`` verb and its subcommands."""
    parser = subparsers.add_parser("study", help="sensitivity (and accuracy) studies",
                                   description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="study", metavar="STUDY")
    sub.required = True
    for add in SUBCOMMANDS.values():
        add(sub)


def run(args):
    """Dispatch to the chosen study (argparse sets ``func`` per subcommand)."""
    return args.func(args)


def _with_table2(identified):
    from motoflex_ros.identify.results import results_source
    from motoflex_ros.study.factorial import PAPER_TABLE2_NOMINAL
    from motoflex_ros.study.motorcycle import with_stiffness

    missing = [c for c in _COMPONENTS if c not in identified]
    if missing:
        raise ConfigError(results_source(identified), missing[0], "missing")
    return with_stiffness(identified, PAPER_TABLE2_NOMINAL)


def _print_tables(result, seconds, stream, unit="N m/rad"):
    rows = [[name, f"{idx.s.min():.4f}", f"{idx.s.mean():.4f}", f"{idx.s.max():.4f}",
             f"{result.anova_main_share[name]:.4f}"] for name, idx in result.indices.items()]
    print_table(["index", "s min", "s mean", "s max", "ANOVA main share"], rows, stream)
    stream.write("\nPearson coefficients (positive: stiffer part, more damping)\n")
    factors = list(result.nominal)
    print_table(["index"] + factors,
                [[name] + [f"{result.pearson[name][f]:+.3f}" for f in factors]
                 for name in result.indices], stream)
    stream.write(f"\nnominal [{unit}]: " + ", ".join(f"{f} {k:.4g}" for f, k in
                                                      result.nominal.items()) + "\n")
    stream.write(f"{len(next(iter(result.indices.values())).s)} runs in {seconds:.2f} s\n")


def _plots(result, run_outputs, speeds, directory):
    from motoflex_ros.plots.study_figures import plot_pearson_bars, plot_stability_curves

    written = [plot_pearson_bars(result.pearson, Path(directory) / "fig10_pearson.png")]
    for mode in STUDIED_MODES:
        written.append(plot_stability_curves(speeds, np.real(run_outputs[mode]),
                                             Path(directory) / f"{mode}_real_parts.png",
                                             mode=mode))
    return written


def agreement(lumped, flexible, negligible=0.05):
    """{index: {factor: {"lumped", "flexible", "difference", "verdict"}}}: Pearson coefficients
    of the lumped and the flexible study side by side; verdict 'same sign', 'opposite',
    'negligible' (both below ``negligible`` in size) or 'no such factor' (the lumped study has
    none of that name: a principal variant without that hinge; lumped and difference None)."""
    out = {}
    for index, row in flexible.pearson.items():
        out[index] = {}
        for factor, rho_f in row.items():
            if factor not in lumped.pearson[index]:
                out[index][factor] = {"lumped": None, "flexible": float(rho_f),
                                      "difference": None, "verdict": "no such factor"}
                continue
            rho_l = lumped.pearson[index][factor]
            if max(abs(rho_l), abs(rho_f)) < negligible:
                verdict = "negligible"
            else:
                verdict = "same sign" if rho_l * rho_f > 0 else "opposite"
            out[index][factor] = {"lumped": float(rho_l), "flexible": float(rho_f),
                                  "difference": float(rho_f - rho_l), "verdict": verdict}
    return out


def _signed(value):
    return "n/a" if value is None else f"{value:+.3f}"


def _flexible_output(args, result, lumped, study_run, speeds):
    from motoflex_ros.study.flexible_sensitivity import MODAL_STIFFNESS

    table = agreement(lumped, result)
    if args.plot:
        written = _plots(result, study_run.outputs, speeds, args.plot)
        if not args.json:
            print("wrote " + ", ".join(str(p) for p in written), file=sys.stderr)
    if args.json:
        emit_json({**result.to_dict(), "definition": MODAL_STIFFNESS, "agreement": table,
                   "lumped": lumped.to_dict()})
        return 0
    sys.stdout.write(MODAL_STIFFNESS + "\n\n")
    _print_tables(result, study_run.seconds, sys.stdout, unit="scale of the modal stiffness")
    variant = "principal" if args.nominal == "principal" else "decomposed"
    sys.stdout.write(f"\nAgreement with the lumped ({variant}) study on the same speeds\n")
    print_table(["index", "factor", "lumped rho", "flexible rho", "difference", "verdict"],
                [[index, factor, _signed(v["lumped"]), _signed(v["flexible"]),
                  _signed(v["difference"]), v["verdict"]]
                 for index, row in table.items() for factor, v in row.items()], sys.stdout)
    return 0


def run_sensitivity_verb(args):
    """``motoflex study sensitivity``; returns the exit code."""
    from motoflex_ros.study.factorial import PAPER_TABLE2_NOMINAL, full_factorial
    from motoflex_ros.study.motorcycle import decomposed_study, principal_study
    from motoflex_ros.study.sensitivity import run_sensitivity
    from motoflex_ros.vehicle.model import load_vehicle

    full_factorial(PAPER_TABLE2_NOMINAL, args.levels, args.rel_range)  # check before the work
    extra = extra_ranges(args)
    step = args.step_kmh if args.step_kmh is not None else (5.0 if args.model == "flexible"
                                                            else 1.0)
    speeds = study_speeds(step, 10.0)
    vehicle = load_vehicle(resolve_config("vehicles", args.vehicle))
    components = motorcycle_components(_COMPONENTS, component_roles(args.use))
    identified = identification_results(args.identified, list(components.values()),
                                        vehicle=args.vehicle)
    if args.nominal == "table2":
        identified = _with_table2(identified)
    lumped_study = principal_study if args.nominal == "principal" else decomposed_study
    setup = lumped_study(vehicle, components, identified, speeds)
    try:
        result, study_run = run_sensitivity(setup.study, setup.nominal, speeds, args.levels,
                                            args.rel_range, args.scheduler, progress=True,
                                            extra_ranges_kmh=extra)
        if args.model == "flexible":
            from motoflex_ros.study.flexible_sensitivity import flexible_study
            lumped = result
            flexible = flexible_study(vehicle, components, identified, speeds)
            result, study_run = run_sensitivity(flexible.study, flexible.nominal, speeds,
                                                args.levels, args.rel_range, args.scheduler,
                                                progress=True, extra_ranges_kmh=extra)
    except OSError as exc:  # includes connection and timeout errors of the Dask client
        raise ConfigError(_ARGS, "--scheduler", f"cannot use {args.scheduler}: {exc}") from None
    if args.model == "flexible":
        return _flexible_output(args, result, lumped, study_run, speeds)
    if args.plot:
        written = _plots(result, study_run.outputs, speeds, args.plot)
        if not args.json:
            print("wrote " + ", ".join(str(p) for p in written), file=sys.stderr)
    if args.json:
        emit_json(result.to_dict())
    else:
        _print_tables(result, study_run.seconds, sys.stdout)
    return 0
