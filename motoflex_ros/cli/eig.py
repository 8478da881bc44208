"""``motoflex eig``: eigenvalues of a vehicle over speed, with weave, wobble and capsize.

    motoflex eig --vehicle FILE (--speeds-kmh V... | --speeds-ms V... | --range-kmh LO HI
                 [--step-kmh S]) [--json] [--plot DIR] [--flex VARIANT]
                 [--component NAME ...] [--identified FILE] [--use FILE ...] [--pulse-check]

Speeds: --speeds-kmh in km/h, --speeds-ms in m/s, --range-kmh LO HI in steps of --step-kmh
(default 5 km/h; inclusive of HI when it falls on the step). The older --speeds (m/s), --step
and comma-separated --components still work, with a deprecation warning.
--json prints {"vehicle", "variant" (of --flex), "components" (made flexible; [] when rigid),
"component_files" ({component: file} of those --use replaced), "speeds_mps", "eigenvalues"
([[re, im], ...] per speed, 1/s), "modes": {"weave", "wobble",
"capsize": [[re, im] | null per speed]}}. --plot DIR writes the root locus and
weave/wobble frequency and real part against speed (PNG).

--flex puts the components' flexibility into the rigid vehicle: ``flexible`` (Craig-Bampton
superelements of the clamped components), ``flexible_bodies`` (the paper's per-body
superelements joined by the vehicle's joints) or a lumped variant (state_of_the_art, static,
torsion, bending, decomposed; Passigato et al. 2023, Sect. 5.2) identified by the bench (run
offline unless --identified gives a result file of ``motoflex identify --out``). --use FILE
puts the engineer's own component (a beam, mesh or superelement YAML) in the role its name
gives it (frame, front_assembly, swingarm); with --identified, the file must hold that
component's identification.

--pulse-check checks the eigenvalues in the time domain at each requested speed: the nonlinear
equations integrated after a 20 N m x 0.05 s steer pulse, weave and wobble read back by the
matrix pencil (:mod:`motoflex_ros.study.pulse_check`; about 6 s of CPU per speed for the rigid
motorcycle, 20 s for a lumped variant, whose stiff hinges need Runge-Kutta sub-steps; a
massless body that carries nothing makes E singular and is refused). --json adds
"pulse_check": [{"speed_mps", "torque_nm", "duration_s", "modes": {mode: {"linear": [re, im],
"nonlinear": [re, im], "frequency_error", "real_error"}}}] (relative errors, -).
"""
import math
import sys
from argparse import SUPPRESS

import numpy as np

from motoflex_ros.cli.inputs import (
    add_use_option,
    component_roles,
    identification_results,
    motorcycle_components,
)
from motoflex_ros.cli.options import add_component_option, deprecated
from motoflex_ros.cli.output import emit_json, print_table
from motoflex_ros.config import resolve_config
from motoflex_ros.errors import ConfigError
from motoflex_ros.limits import check_limit
from motoflex_ros.study.identified_variants import build_variant
from motoflex_ros.study.pulse_check import pulse_check
from motoflex_ros.units import kmh_to_ms, ms_to_kmh
from motoflex_ros.vehicle.linearize import linearize
from motoflex_ros.vehicle.mode_names import MODE_NAMES
from motoflex_ros.vehicle.model import load_vehicle
from motoflex_ros.vehicle.modes import modal_sweep
from motoflex_ros.vehicle.schema import SPEED_MAX_MPS
from motoflex_ros.vehicle.variants import FLEX_CHOICES, FLEXIBLE, parse_components

__all__ = ["register", "run", "requested_speeds", "sweep_to_json", "model_to_json",
           "pulse_check_to_json"]

_ARGS = "command line"
STEP_KMH = 5.0   # default step of --range-kmh [km/h]


def register(subparsers):
    parser = subparsers.add_parser(
        "eig", help="weave, wobble and capsize eigenvalues of a vehicle over speed",
        description="Linearize a vehicle (config/vehicles/*.yaml) about straight running and "
                    "print its eigenvalues over speed, with weave, wobble and capsize tracked "
                    "by mode shape.")
    parser.add_argument("--vehicle", required=True,
                        help="vehicle YAML file, or the name of a shipped vehicle (touring)")
    speeds = parser.add_mutually_exclusive_group(required=True)
    speeds.add_argument("--speeds-kmh", type=float, nargs="+", metavar="V", help="speeds [km/h]")
    speeds.add_argument("--speeds-ms", type=float, nargs="+", metavar="V", help="speeds [m/s]")
    speeds.add_argument("--speeds", type=float, nargs="+", dest="speeds_ms",
                        action=deprecated("--speeds-ms (or --speeds-kmh)"), help=SUPPRESS,
                        default=SUPPRESS)
    speeds.add_argument("--range-kmh", type=float, nargs=2, metavar=("LO", "HI"),
                        help="speed range [km/h]")
    parser.add_argument("--step-kmh", type=float, default=STEP_KMH, metavar="S",
                        help="step of --range-kmh [km/h]")
    parser.add_argument("--step", type=float, dest="step_kmh", action=deprecated("--step-kmh"),
                        help=SUPPRESS, default=SUPPRESS)
    parser.add_argument("--json", action="store_true", help="print JSON only")
    parser.add_argument("--plot", metavar="DIR", help="write root locus and mode plots (PNG)")
    parser.add_argument("--flex", default="rigid", choices=FLEX_CHOICES,
                        help="rigid (default), flexible, flexible_bodies or a lumped "
                             "stiffness variant")
    add_component_option(parser, "a component made flexible; repeatable (default: all three)")
    parser.add_argument("--identified", metavar="FILE",
                        help="identification results (YAML/JSON of motoflex identify --out)")
    add_use_option(parser)
    parser.add_argument("--pulse-check", action="store_true",
                        help="also check weave and wobble at each speed against the nonlinear "
                             "response to a small steer pulse (seconds per speed)")
    parser.set_defaults(func=run)


def requested_speeds(args):
    """Speeds [m/s] from --speeds-kmh, --speeds-ms or --range-kmh/--step-kmh; ConfigError on
    bad values, on a speed above SPEED_MAX_MPS and on more speeds than the 'speeds' limit (sized
    before any array). Errors give the speed in the option's own unit."""
    given = [(key, values, unit) for key, values, unit in
             (("--speeds-kmh", args.speeds_kmh, "km/h"), ("--speeds-ms", args.speeds_ms, "m/s"))
             if values is not None]
    if given:
        key, values, unit = given[0]
        check_limit("speeds", len(values), _ARGS, key)
        given_speeds = np.asarray(values, float)
    else:
        step = args.step_kmh
        if step is None or not step > 0:
            raise ConfigError(_ARGS, "--step-kmh", "give a step > 0 km/h with --range-kmh")
        low, high = args.range_kmh
        if not high >= low:
            raise ConfigError(_ARGS, "--range-kmh", f"HI {high:g} must be >= LO {low:g}")
        key, unit = "--range-kmh", "km/h"
        check_top_speed(kmh_to_ms(high), key, unit)
        count = math.floor((high - low) / step + 1e-9) + 1
        check_limit("speeds", count, _ARGS, "--step-kmh", f"--range-kmh {low:g} {high:g} in "
                                                          f"steps of {step:g} km/h")
        given_speeds = low + step * np.arange(count)
    bad = given_speeds[~(np.isfinite(given_speeds) & (given_speeds > 0))]
    if bad.size:
        raise ConfigError(_ARGS, key, f"speeds must be finite and > 0 {unit}, "
                                      f"got {bad[0]:g} {unit}")
    speeds = kmh_to_ms(given_speeds) if unit == "km/h" else given_speeds
    check_top_speed(speeds.max(), key, unit)
    return speeds


def check_top_speed(speed, key, unit="m/s", source=_ARGS):
    """ConfigError when a speed [m/s] is above SPEED_MAX_MPS (400 km/h); the message gives
    the speed in ``unit`` (the option's: 'm/s' or 'km/h')."""
    if not speed <= SPEED_MAX_MPS:
        shown = ms_to_kmh(speed) if unit == "km/h" else speed
        raise ConfigError(source, key, f"speeds must be at most {SPEED_MAX_MPS:.4g} m/s "
                                       f"({ms_to_kmh(SPEED_MAX_MPS):g} km/h), "
                                       f"got {shown:g} {unit}")


def _pair(z):
    return None if not np.isfinite(z) else [float(z.real), float(z.imag)]


def sweep_to_json(sweep):
    """The JSON document of a ModalSweep (shape in the module docstring)."""
    return {"speeds_mps": [float(v) for v in sweep.speeds],
            "eigenvalues": [[[float(z.real), float(z.imag)] for z in ev]
                            for ev in sweep.eigenvalues],
            "modes": {name: [_pair(z) for z in sweep.modes[name]] for name in MODE_NAMES}}


def model_to_json(args):
    """What the eigenvalues are of: {"vehicle", "variant", "components", "component_files"}
    of the arguments (``component_files``: {role: file} of ``--use``, the components that are
    not the shipped ones)."""
    rigid = args.flex == "rigid"
    names = [] if rigid else parse_components(args.component)
    roles = component_roles(args.use)
    return {"vehicle": args.vehicle, "variant": args.flex, "components": names,
            "component_files": {name: roles[name] for name in names if name in roles}}


def _cell(z, part):
    if not np.isfinite(z):
        return "-"
    return f"{z.imag / (2 * np.pi):.3f}" if part == "f" else f"{z.real:.3f}"


def _print_table(sweep, stream):
    rows = []
    for k, v in enumerate(sweep.speeds):
        m = {name: sweep.modes[name][k] for name in MODE_NAMES}
        rows.append([f"{ms_to_kmh(v):.1f}", _cell(m["weave"], "f"), _cell(m["weave"], "re"),
                     _cell(m["wobble"], "f"), _cell(m["wobble"], "re"),
                     _cell(m["capsize"], "re")])
    print_table(["speed km/h", "weave Hz", "weave Re 1/s", "wobble Hz", "wobble Re 1/s",
                 "capsize 1/s"], rows, stream)


def pulse_check_to_json(check):
    """The JSON entry of one PulseCheck (shape in the module docstring)."""
    errors = check.relative_errors()
    return {"speed_mps": float(check.speed), "torque_nm": float(check.torque),
            "duration_s": float(check.duration),
            "modes": {m: {"linear": _pair(lam), "nonlinear": _pair(check.nonlinear[m]),
                          "frequency_error": float(errors[m][0]),
                          "real_error": float(errors[m][1])}
                      for m, lam in check.linear.items()}}


def _print_pulse_checks(checks, stream):
    rows = [[f"{ms_to_kmh(c.speed):.1f}", mode, f"{lam.imag / (2 * np.pi):.3f}", f"{lam.real:.3f}",
             f"{c.nonlinear[mode].imag / (2 * np.pi):.3f}", f"{c.nonlinear[mode].real:.3f}",
             f"{100 * err[0]:+.3f}", f"{100 * err[1]:+.3f}"]
            for c in checks for mode, lam in c.linear.items()
            for err in [c.relative_errors()[mode]]]
    stream.write(f"\nnonlinear steer pulse ({checks[0].torque:g} N m x {checks[0].duration:g} s)"
                 " read by the matrix pencil against the eigenvalues\n")
    print_table(["speed km/h", "mode", "eig Hz", "eig Re 1/s", "pulse Hz", "pulse Re 1/s",
                 "f error %", "Re error %"], rows, stream)


def variant_of(model, args):
    """The vehicle with the flexibility asked for by --flex/--components/--identified."""
    if args.flex == "rigid":
        return model
    names = parse_components(args.component)
    components = motorcycle_components(names, component_roles(args.use))
    identified = {}
    if args.flex not in FLEXIBLE:
        identified = identification_results(args.identified, list(components.values()))
    return build_variant(model, args.flex, names, identified, components)


def run(args):
    speeds = requested_speeds(args)
    model = variant_of(load_vehicle(resolve_config("vehicles", args.vehicle)), args)
    lin = linearize(model)
    sweep = modal_sweep(lin, speeds)
    checks = [pulse_check(lin, v) for v in speeds] if args.pulse_check else []
    if args.plot:
        from motoflex_ros.plots.vehicle import plot_modal_sweep
        written = plot_modal_sweep(sweep, args.plot, model.name)
        if not args.json:
            print("wrote " + ", ".join(str(p) for p in written), file=sys.stderr)
    if args.json:
        extra = {"pulse_check": [pulse_check_to_json(c) for c in checks]} if checks else {}
        emit_json({**model_to_json(args), **sweep_to_json(sweep), **extra})
    else:
        _print_table(sweep, sys.stdout)
        if checks:
            _print_pulse_checks(checks, sys.stdout)
    return 0
