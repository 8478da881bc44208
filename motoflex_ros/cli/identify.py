"""``motoflex identify``: the bench campaign offline (no ROS), per component.

Static test, harmonic tests at the first torsion and bending frequencies, the sweep and the
modal test (Passigato et al. 2023, Sect. 4.2), and beyond the paper the two moment tests of
the principal hinges (:mod:`motoflex_ros.identify.principal`; their metric from the touring
motorcycle's bodies each loaded end carries); prints a table or, with --json, the results
{component: {"static", "torsion", "bending", "k_t", "k_b", "sweep", "principal", ...}} (angles
rad, lengths m, stiffness N m/rad), optionally writes them to a YAML/JSON file and the Figs.
5-7 plots.

``--measured FILE --bench BENCH.yaml``: the same identification of a physical rig's
measurements (a CSV file or a rosbag2 folder), without a finite-element model
(:mod:`motoflex_ros.identify.measured`); the results are filed under the bench's name.
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
from motoflex_ros.formats.json_yaml import write_results

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
    p.add_argument("--vehicle", default="touring", metavar="NAME|FILE",
                   help="the motorcycle whose bodies the loaded ends carry: the principal "
                        "hinges' metric (shipped name or vehicle YAML; default: touring)")
    p.add_argument("--out", metavar="FILE", help="write the results (.yaml/.yml or .json); "
                                                 "an existing file only with --force")
    add_force_option(p)
    p.add_argument("--json", action="store_true", help="print the results as JSON only")
    p.add_argument("--plot", metavar="DIR", help="write the Figs. 5-7 axis plots to DIR")
    p.add_argument("--measured", metavar="FILE",
                   help="identify a real rig's measurements instead: a CSV file (header "
                        "t,test,fx,fy,fz,mx,my,mz,m1_x,m1_y,m1_z,...) or a rosbag2 folder "
                        "(WrenchStamped loads, PoseArray or per-marker PointStamped/"
                        "PoseStamped markers); needs --bench")
    p.add_argument("--bench", metavar="BENCH.yaml",
                   help="bench file of --measured: bench, loaded_end, markers, sensor")
    p.add_argument("--load-topic", metavar="TOPIC",
                   help="--measured bag: the load cell's topic (default /bench/<bench>/load, "
                        "else the bag's only WrenchStamped topic)")
    p.add_argument("--markers-topic", metavar="TOPIC", action="append",
                   help="--measured bag: the markers' PoseArray topic, or one PointStamped/"
                        "PoseStamped topic per marker in marker order (repeat); default "
                        "/bench/<bench>/markers/measured, else the bag's only PoseArray topic")
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
            if r is None:   # a measured record without that test
                rows.append([name, test, "n/a", "n/a", "n/a", "n/a", "n/a", ""])
                continue
            rows.append([name, test, f"{r['l']:.4f}", f"{r['beta']:.4f}", f"{r['b']:.4f}",
                         _number(r["k"]), format_interval(r["ci"].get("k")),
                         f"{r.get('f_hz', 0.0):.2f}"])
        for key in ("k_t", "k_b"):
            rows.append([name, f"{key} (eq. 12)", "", "", "", _number(comp[key]),
                         format_interval(comp["ci"].get(key)), ""])
    print_table(["component", "test", "l [m]", "beta [rad]", "b [m]", "k [N m/rad]",
                 "k 95 % interval", "f [Hz]"], rows, stream)
    _modal_table(results, stream)
    _principal_table(results, stream)
    for name, comp in results.items():
        if comp.get("split_identifiable") is False:
            stream.write(f"warning: {name}: k_t, k_b not identifiable: "
                         f"{comp['split_problem']}\n")


def _principal_table(results, stream):
    """The principal hinges (beyond the paper) with the three directions' lambda and f; a note
    per component where they are not identified."""
    rows, notes = [], []
    for name, comp in results.items():
        p = comp.get("principal")
        if not p:
            continue
        if not p["identified"]:
            notes.append(f"note: {name}: principal hinges not identified: {p['problem']}\n")
            continue
        for i, h in enumerate(p["hinges"]):
            rows.append([name, f"principal {i + 1}", f"{h['l']:.4f}", f"{h['beta']:.4f}",
                         f"{h['b']:.4f}", _number(h["k"]), format_interval(h["ci"].get("k")),
                         _number(p["f_hz"][i], ".4g")])
        dropped = ", ".join(f"{f:.4g}" for f in p["f_hz"][len(p["hinges"]):]
                            if f is not None and math.isfinite(f))
        notes.append(f"{name}: principal directions lambda = "
                     f"{', '.join(f'{v:.4g}' for v in p['lambda_s2'])} s^2; kept "
                     f"{p['n_hinges']} (dropped f: {dropped or 'none'} Hz)\n")
    if rows:
        stream.write("\n")
        print_table(["component", "hinge", "l [m]", "beta [rad]", "b [m]", "k [N m/rad]",
                     "k 95 % interval", "f carried [Hz]"], rows, stream)
    for note in notes:
        stream.write(note)


def _modal_table(results, stream):
    """Eigenvalue (eq. 9) beside the free decay's omega_n, zeta and their 95 % intervals."""
    rows = []
    for name, comp in results.items():
        for label in ("torsion", "bending"):
            m = comp.get("modal", {}).get(label)
            if m is None:
                continue
            ci = m.get("ci", {})
            rows.append([name, label, _number(m["omega_n"], ".6g"),
                         _number(m["omega_n_decay"], ".6g"),
                         format_interval(ci.get("omega_n_decay"), ".6g"), _number(m["zeta"]),
                         _number(m["zeta_decay"]), format_interval(ci.get("zeta_decay"))])
    if rows:
        stream.write("\n")
        print_table(["component", "mode", "omega_n [rad/s]", "decay", "95 % interval",
                     "zeta", "decay", "95 % interval"], rows, stream)


def _measured_inputs(args):
    """The Measurements and PhysicalBench of --measured/--bench (ConfigError naming the option
    when one is missing or combined with the virtual bench's options)."""
    from motoflex_ros.errors import ConfigError
    from motoflex_ros.formats.bench_file import load_bench
    if not args.bench:
        raise ConfigError("command line", "--bench", "--measured needs the bench file "
                                                     "(--bench BENCH.yaml: bench, loaded_end, "
                                                     "markers, sensor)")
    for option, value in (("--component", args.component), ("--protocol", args.protocol),
                          ("--noise", args.noise),
                          ("--vehicle", args.vehicle if args.vehicle != "touring" else None)):
        if value:
            raise ConfigError("command line", option, f"{option} is for the virtual bench; "
                                                      f"a measured rig has no model (give "
                                                      f"--measured and --bench only)")
    bench = load_bench(args.bench)
    path = Path(args.measured)
    if path.is_dir():
        from motoflex_ros.record.measured_bag import read_bag
        return read_bag(path, bench, args.load_topic, args.markers_topic), bench
    from motoflex_ros.formats.measured_csv import read_csv
    return read_csv(path, bench.latency_s), bench


def run_measured(args):
    """``identify --measured``: the measurements' identification; returns the exit code."""
    from motoflex_ros.identify.measured import identify_measured
    if args.out:
        check_new_file(args.out, args.force)
    data, bench = _measured_inputs(args)
    identification = identify_measured(data, bench)
    results = {bench.name: identification.to_dict()}
    if args.out:
        write_results(args.out, results)
    if args.plot:
        from motoflex_ros.plots.axes import plot_measured_axes
        plot_measured_axes(bench.name, bench.q0, results[bench.name],
                           Path(args.plot) / f"{bench.name}_axes.png")
    if args.json:
        emit_json(results)
    else:
        _table(results)
        _measured_summary(results[bench.name]["measured"])
        sys.stdout.flush()
    return 0


def _measured_summary(measured, stream=None):
    """The tests found in the measurements and the frame counts."""
    stream = stream or sys.stdout
    rows = [[e["name"], e["kind"], e.get("model") or "", f"{e['t_start']:.4f}",
             f"{e['t_end']:.4f}", f"{e['frequency_hz']:.4g}" if e["frequency_hz"] else "",
             f"{e['amplitude_n']:.4g}", "yes" if e["used"] else "no"]
            for e in measured["tests"]]
    stream.write("\n")
    print_table(["test", "kind", "model", "t start [s]", "t end [s]", "f [Hz]", "load [N|N m]",
                 "used"], rows, stream)
    c = measured["counts"]
    stream.write(f"\n{measured['frames']} frames of {measured['markers']} markers; dropped: "
                 f"{c['dropped_marker_frames']} marker frames, {c['dropped_load_samples']} "
                 f"load samples; unmatched: {c['unmatched_frames']}; reference: "
                 f"{measured['reference']}\n")
    for note in measured["notes"]:
        stream.write(f"note: {note}\n")
    for e in measured["tests"]:
        if not e["used"]:
            stream.write(f"note: {e['name']} not used: {e['note']}\n")


def run(args):
    """Run the campaign of each component; returns the exit code."""
    if args.measured:
        return run_measured(args)
    from motoflex_ros.bench.offline_campaign import identify_components
    from motoflex_ros.formats.component_file import load_components
    from motoflex_ros.study.identified_variants import carried_inertias
    if args.out:
        check_new_file(args.out, args.force)
    components = load_components(args.component or list(DEFAULT_COMPONENTS))
    carried = carried_inertias(components, args.vehicle)
    if args.protocol:   # a bad protocol is refused before the work (and its progress) starts
        from motoflex_ros.bench.protocols import load_protocol
        load_protocol(args.protocol)
    with progress_bar(len(components), "bench identification", "component") as bar:
        runs = identify_components(components, args.protocol, args.noise, args.seed,
                                   progress=lambda _name: bar.update(1), carried=carried)
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
