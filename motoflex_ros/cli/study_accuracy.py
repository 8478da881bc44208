"""``motoflex study accuracy``: lumped models against the flexible motorcycle (Sect. 5.2).

    motoflex study accuracy [--identified FILE] [--vehicle touring] [--step-kmh 5] [--json]
                            [--cases LIST] [--plot DIR] [--details FILE [--force]]
                            [--vehicle-load-kmh 100] [--vehicle-load-mode wobble]

Runs the bench identification (or reads --identified), builds the flexible motorcycle and every
lumped variant for the frame, the front assembly, the swingarm and all three, sweeps 40-210
km/h and prints e_RMS% (eq. 18) of weave and wobble frequency and real part. The variants are
the paper's (state_of_the_art, static, torsion, bending) and three single hinges beyond it:
road_load and vehicle_load (bench tests loaded through a lever at the tyre contact point, and
by the wrench the component carries in the flexible motorcycle's wobble) and fitted (the hinge
fitted to the flexible motorcycle). Then the hinges (l, beta, b, k) of each, the
conditioning of the fitted one and, beside it, the errors of the motorcycle with the FE
model's whole end stiffness in the hinge's place. --json prints {case: {variant: {"weave_f",
"weave_re", "wobble_f", "wobble_re"}}} in percent; --details FILE writes the hinges, the fits
(start, objective, conditioning, end_stiffness_errors) and the load tests as JSON. --plot DIR
writes the Fig. 8 bars and the Fig. 9 curves of the front assembly.
"""
import json
import math
import sys
from pathlib import Path

from motoflex_ros.cli.inputs import (
    add_study_inputs,
    component_roles,
    identification_results,
    motorcycle_components,
    study_speeds,
)
from motoflex_ros.cli.output import (
    add_force_option,
    check_new_file,
    emit_json,
    print_table,
    progress_bar,
)
from motoflex_ros.config import resolve_config
from motoflex_ros.errors import ConfigError
from motoflex_ros.files import atomic_write_text
from motoflex_ros.formats.json_yaml import to_jsonable
from motoflex_ros.units import kmh_to_ms, ms_to_kmh

__all__ = ["register_accuracy", "run_accuracy", "print_hinges", "details"]


def register_accuracy(sub):
    """Add the ``accuracy`` study to the ``study`` verb's subparsers."""
    p = sub.add_parser("accuracy", help="e_RMS%% of lumped models vs flexible (Figs 8-9)",
                       description=__doc__.splitlines()[0])
    add_study_inputs(p)
    p.add_argument("--step-kmh", type=float, default=5.0, help="speed step [km/h] (default 5)")
    p.add_argument("--json", action="store_true", help="print JSON only")
    p.add_argument("--plot", metavar="DIR", help="write Fig. 8 bars and Fig. 9 curves (PNG)")
    p.add_argument("--cases", metavar="LIST",
                   help="comma-separated cases (frame, front_assembly, swingarm, all; default "
                        "every one)")
    p.add_argument("--details", metavar="FILE",
                   help="write the hinges, fits, conditioning and load tests (JSON)")
    add_force_option(p)
    p.add_argument("--vehicle-load-kmh", type=float, default=100.0,
                   help="speed [km/h] of the mode loading the vehicle_load test (default 100)")
    p.add_argument("--ground-truth", choices=("flexible", "flexible_bodies"), default="flexible",
                   help="the flexible motorcycle: one clamped superelement per component "
                        "(default) or the per-body superelements joined by the vehicle's "
                        "joints (slower: about 2 min)")
    p.add_argument("--vehicle-load-mode", choices=("wobble", "weave"), default="wobble",
                   help="mode whose wrench loads the vehicle_load test (default wobble)")
    p.set_defaults(func=run_accuracy)


def _print(result, stream):
    rows = [[case, variant] + [f"{values[q]:.2f}" for q in values]
            for case, table in result.errors.items() for variant, values in table.items()]
    print_table(["case", "variant", "weave f %", "weave Re %", "wobble f %", "wobble Re %"],
                rows, stream)
    if result.fits or result.loads:
        stream.write("\n")
        print_hinges(result, stream)


def _hinge_row(component, label, values):
    return [component, label, f"{values['l']:.4f}", f"{math.degrees(values['beta']):.2f}",
            f"{values['b']:.4f}", f"{values['k']:.4g}"]


def print_hinges(result, stream):
    """The single hinges beside the static one, the fits and their conditioning."""
    from motoflex_ros.study.hinge_fit_problem import objective_of

    stream.write("Single hinges (component frame, eqs. 5-8; c = 0.001 s x k). 'all' uses each "
                 "component's own, unchanged\n")
    rows = []
    for name in {**result.loads, **result.fits}:
        fit, loads = result.fits.get(name), result.loads.get(name, {})
        static = fit.static[name].to_dict() if fit else None
        if static:
            rows.append(_hinge_row(name, "static", static))
        for test in ("road_load", "vehicle_load"):
            if test in loads:
                rows.append(_hinge_row(name, test, loads[test].model.values))
        if fit:
            rows.append(_hinge_row(name, "fitted", fit.hinges[name].to_dict()))
    print_table(["component", "hinge", "l [m]", "beta [deg]", "b [m]", "k [N m/rad]"], rows,
                stream)
    for name, loads in result.loads.items():
        carried = loads["wrench"]
        w = carried.direction
        stream.write(f"vehicle_load of {name}: {carried.mode} at "
                     f"{ms_to_kmh(carried.speed):.0f} km/h, wrench at q0 per N of force "
                     f"F ({w[0]:+.3f}, {w[1]:+.3f}, {w[2]:+.3f}), M ({w[3]:+.3f}, "
                     f"{w[4]:+.3f}, {w[5]:+.3f}) m\n")
    for name, fit in result.fits.items():
        stream.write(f"\nfitted {name}: J = sqrt(sum of the four e_RMS%^2) "
                     f"{objective_of(fit.static_errors):.3f} % (static) -> "
                     f"{objective_of(fit.errors):.3f} %; searched from static and "
                     f"{', '.join(k for k in fit.starts if k != 'static') or 'nothing else'} "
                     f"(ends: " + ", ".join(f"{k} {v['objective']:.3f} %"
                                           for k, v in fit.starts.items())
                     + "; searched on fewer speeds), best from "
                     f"{fit.start}; {fit.evaluations} "
                     f"evaluations, {fit.seconds:.1f} s\n")
        stream.write("conditioning (e_RMS% with one change, the rest at the optimum; axis "
                     "turned about its point nearest q0, moved normal to itself):\n")
        rows = [[label] + [f"{e[q]:.2f}" for q in e] + [f"{max(e.values()):.2f}"]
                for label, e in fit.conditioning[name].items()]
        rows.insert(0, ["optimum"] + [f"{fit.errors[q]:.2f}" for q in fit.errors]
                    + [f"{max(fit.errors.values()):.2f}"])
        print_table(["change", "weave f %", "weave Re %", "wobble f %", "wobble Re %",
                     "largest %"], rows, stream)
        spring = fit.spring_errors
        stream.write("the FE model's whole end stiffness (6 x 6, massless) in the hinge's "
                     "place: " + (", ".join(f"{q} {v:.2f} %" for q, v in spring.items())
                                  if spring else "weave or wobble not followed") + "\n")


def details(result):
    """The JSON of ``--details``: "errors" (the --json table) and per component ("components")
    the fit and the load tests."""
    out = {}
    for name in {**result.loads, **result.fits}:
        entry = {}
        if name in result.fits:
            entry["fit"] = result.fits[name].to_dict()
        if name in result.loads:
            loads = result.loads[name]
            carried = loads["wrench"]
            entry["road_load"] = loads["road_load"].to_dict()
            entry["vehicle_load"] = {**loads["vehicle_load"].to_dict(), "mode": carried.mode,
                                     "speed_mps": carried.speed,
                                     "eigenvalue": [carried.eigenvalue.real,
                                                    carried.eigenvalue.imag],
                                     "mode_wrench": list(carried.wrench)}
        out[name] = entry
    return {"errors": result.to_dict(), "components": out}


def _cases(text, allowed):
    if text in (None, ""):
        return list(allowed)
    names = [n.strip() for n in text.split(",") if n.strip()]
    unknown = [n for n in names if n not in allowed]
    if unknown or not names:
        raise ConfigError("command line", "--cases", f"unknown case '{(unknown or [text])[0]}' "
                                                     f"(allowed: {', '.join(allowed)})")
    return names


def _load_speed(kmh):
    if not 40.0 <= kmh <= 210.0:
        raise ConfigError("command line", "--vehicle-load-kmh",
                          f"must be in [40, 210] km/h (the study's range), got {kmh:g}")
    return float(kmh_to_ms(kmh))


def run_accuracy(args):
    """``motoflex study accuracy``; returns the exit code."""
    from motoflex_ros.plots.accuracy_figure import plot_mode_curves
    from motoflex_ros.plots.study_figures import plot_accuracy_bars
    from motoflex_ros.study.lumped_accuracy import ACCURACY_VARIANTS, CASES, accuracy_study
    from motoflex_ros.vehicle.model import load_vehicle

    details_path = check_new_file(args.details, args.force, "--details") if args.details \
        else None
    cases = _cases(args.cases, CASES)
    load_speed = _load_speed(args.vehicle_load_kmh)
    speeds = study_speeds(args.step_kmh, 85.0)
    vehicle = load_vehicle(resolve_config("vehicles", args.vehicle))
    components = motorcycle_components(roles=component_roles(args.use))
    needed = [n for n in components if n in cases or "all" in cases]
    identified = identification_results(args.identified, [components[n] for n in needed],
                                        vehicle=args.vehicle)
    with progress_bar(len(cases) * (1 + len(ACCURACY_VARIANTS)), "models", "model") as bar:
        result = accuracy_study(vehicle, components, identified, speeds, cases=cases,
                                progress=lambda: bar.update(1), vehicle_load_speed=load_speed,
                                vehicle_load_mode=args.vehicle_load_mode,
                                ground_truth=args.ground_truth)
    if details_path:
        atomic_write_text(details_path, json.dumps(to_jsonable(details(result)), indent=1,
                                                   allow_nan=False) + "\n")
    if args.plot:
        folder = Path(args.plot)
        written = [plot_accuracy_bars(result.to_dict(), folder / "fig8_accuracy.png")]
        if "front_assembly" in result.curves:
            written.append(plot_mode_curves(result.speeds, result.curves["front_assembly"],
                                            folder / "fig9_front_assembly.png"))
        if not args.json:
            print("wrote " + ", ".join(str(p) for p in written), file=sys.stderr)
    if args.json:
        emit_json(result.to_dict())
    else:
        _print(result, sys.stdout)
    return 0
