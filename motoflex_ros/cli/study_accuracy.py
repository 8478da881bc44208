"""``motoflex study accuracy``: lumped models against the flexible motorcycle (Sect. 5.2).

    motoflex study accuracy [--identified FILE] [--vehicle touring] [--step-kmh 5] [--json]
                            [--plot DIR]

Runs the bench identification (or reads --identified), builds the flexible motorcycle and every
lumped variant for the frame, the front assembly, the swingarm and all three, sweeps 40-210
km/h and prints e_RMS% (eq. 18) of weave and wobble frequency and real part. --json prints
{case: {variant: {"weave_f", "weave_re", "wobble_f", "wobble_re"}}} in percent. --plot DIR
writes the Fig. 8 bars and the Fig. 9 curves of the front assembly.
"""
import sys
from pathlib import Path

from motoflex_ros.cli.inputs import (
    add_study_inputs,
    identification_results,
    motorcycle_components,
    study_speeds,
)
from motoflex_ros.cli.output import emit_json, print_table, progress_bar
from motoflex_ros.config import resolve_config

__all__ = ["register_accuracy", "run_accuracy"]


def register_accuracy(sub):
    """Add the ``accuracy`` study to the ``study`` verb's subparsers."""
    p = sub.add_parser("accuracy", help="e_RMS%% of lumped models vs flexible (Figs 8-9)",
                       description=__doc__.splitlines()[0])
    add_study_inputs(p)
    p.add_argument("--step-kmh", type=float, default=5.0, help="speed step [km/h] (default 5)")
    p.add_argument("--json", action="store_true", help="print JSON only")
    p.add_argument("--plot", metavar="DIR", help="write Fig. 8 bars and Fig. 9 curves (PNG)")
    p.set_defaults(func=run_accuracy)


def _print(result, stream):
    rows = [[case, variant] + [f"{values[q]:.2f}" for q in values]
            for case, table in result.errors.items() for variant, values in table.items()]
    print_table(["case", "variant", "weave f %", "weave Re %", "wobble f %", "wobble Re %"],
                rows, stream)


def run_accuracy(args):
    """``motoflex study accuracy``; returns the exit code."""
    from motoflex_ros.plots.accuracy import plot_mode_curves
    from motoflex_ros.plots.study import plot_accuracy_bars
    from motoflex_ros.study.lumped_accuracy import ACCURACY_VARIANTS, CASES, accuracy_study
    from motoflex_ros.vehicle.model import load_vehicle

    speeds = study_speeds(args.step_kmh, 85.0)
    vehicle = load_vehicle(resolve_config("vehicles", args.vehicle))
    identified = identification_results(args.identified)
    components = motorcycle_components()
    with progress_bar(len(CASES) * (1 + len(ACCURACY_VARIANTS)), "models", "model") as bar:
        result = accuracy_study(vehicle, components, identified, speeds,
                                progress=lambda: bar.update(1))
    if args.plot:
        folder = Path(args.plot)
        written = [plot_accuracy_bars(result.to_dict(), folder / "fig8_accuracy.png"),
                   plot_mode_curves(result.speeds, result.curves["front_assembly"],
                                    folder / "fig9_front_assembly.png")]
        if not args.json:
            print("wrote " + ", ".join(str(p) for p in written), file=sys.stderr)
    if args.json:
        emit_json(result.to_dict())
    else:
        _print(result, sys.stdout)
    return 0
