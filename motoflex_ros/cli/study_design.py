"""``motoflex study design``: sections for weave and wobble stability at least mass (issue 26).

    motoflex study design [--space FILE] [--json] [--out DIR] [--plot DIR] [--seed N]
                          [--scheduler ADDRESS|local] [--pop-size 40] [--generations 10]
                          [--maxiter 40] [--max-points 24] [--step-kmh 5]

Reads a design space (default: the shipped config/design/touring.yaml), evaluates designs on
the flexible motorcycle with all three components as superelements (re-reduction and the exact
update of E(v), A(v); weave and wobble by continuation; eqs. 13-15), finds the least structural
mass under the floors (scipy SLSQP) and the front of mass against the smallest stability margin
(pymoo NSGA-II), re-evaluates every reported design by a full linearization and prints them.
--json prints {"nominal": {"mass_kg", "indices"}, "pareto": [{"mass_kg", "indices",
"variables", "full_check"}], "lightest_feasible": {"mass_kg", "indices", "variables",
"full_check", "files": {component: path}} (null when none), "why_none", "floors",
"stiffness_change", "seconds", "evaluations"}. --out DIR writes the component files of the
lightest feasible design (DIR/lightest_feasible/<component>.yaml, for ``motoflex eig --use``)
and of each Pareto point (DIR/pareto_NN/). --plot DIR writes design_front.png and
design_stiffness.png.
"""
import sys
from pathlib import Path

from motoflex_ros.cli.inputs import study_speeds
from motoflex_ros.cli.output import emit_json, print_table
from motoflex_ros.config import MOTORCYCLE_COMPONENTS, resolve_config
from motoflex_ros.errors import ConfigError
from motoflex_ros.files import atomic_write_text

__all__ = ["register_design", "run_design", "write_design_files"]

_ARGS = "command line"


def register_design(sub):
    """Add the ``design`` study to the ``study`` verb's subparsers."""
    p = sub.add_parser("design", help="sections for stability at least mass (Pareto front)",
                       description=__doc__.splitlines()[0])
    p.add_argument("--space", default="touring",
                   help="design space YAML or shipped name (default touring)")
    p.add_argument("--json", action="store_true", help="print JSON only")
    p.add_argument("--out", metavar="DIR", help="write the designs' component files here")
    p.add_argument("--plot", metavar="DIR", help="write the front and stiffness plots (PNG)")
    p.add_argument("--seed", type=int, default=0, help="seed of NSGA-II (default 0)")
    p.add_argument("--scheduler", metavar="ADDRESS",
                   help="run the evaluations on Dask: a scheduler address or 'local'")
    p.add_argument("--pop-size", type=int, default=40, help="NSGA-II population (default 40)")
    p.add_argument("--generations", type=int, default=10,
                   help="NSGA-II generations (default 10)")
    p.add_argument("--maxiter", type=int, default=40, help="SLSQP iterations (default 40)")
    p.add_argument("--max-points", type=int, default=24,
                   help="Pareto points reported, spread over the front (default 24)")
    p.add_argument("--step-kmh", type=float, default=5.0, help="speed step [km/h] (default 5)")
    p.set_defaults(func=run_design)


def _check_counts(args):
    for option, value, low, high in (("--pop-size", args.pop_size, 4, 1000),
                                     ("--generations", args.generations, 1, 1000),
                                     ("--maxiter", args.maxiter, 1, 1000),
                                     ("--max-points", args.max_points, 1, 1000)):
        if not low <= value <= high:
            raise ConfigError(_ARGS, option, f"must be in [{low}, {high}], got {value}")


def write_design_files(result, directory):
    """Write the component files of the lightest feasible design and of each Pareto point
    under ``directory``; returns {component: path} of the lightest feasible design."""
    from motoflex_ros.formats.design_space_file import design_component_text

    space, root = result.space, Path(directory)
    designs = [(f"pareto_{i:02d}", f"Pareto point {i}", p) for i, p in enumerate(result.pareto)]
    if result.lightest is not None:
        designs.insert(0, ("lightest_feasible", "lightest feasible design", result.lightest))
    files = {}
    for folder, label, point in designs:
        (root / folder).mkdir(parents=True, exist_ok=True)
        for component in space.components():
            path = root / folder / f"{component}.yaml"
            atomic_write_text(path, design_component_text(space, component, point.x, label))
            if folder == "lightest_feasible":
                files[component] = str(path)
    return files


def _setup(args):
    from motoflex_ros.formats.component_file import load_component
    from motoflex_ros.formats.design_space_file import held_members_mass, load_design_space
    from motoflex_ros.study.design_evaluate import design_evaluator
    from motoflex_ros.study.design_study import FullEvaluator
    from motoflex_ros.vehicle.model import load_vehicle

    space = load_design_space(args.space)
    speeds = study_speeds(args.step_kmh, 10.0)
    vehicle = load_vehicle(resolve_config("vehicles", space.vehicle))
    components = {n: load_component(space.sources.get(n, n)) for n in MOTORCYCLE_COMPONENTS}
    static_k = any("min_static_k" in f for f in space.floors.values())
    evaluator = design_evaluator(space, vehicle, components, speeds,
                                 held_members_mass(space, components), static_k=static_k)
    return evaluator, FullEvaluator(space, vehicle, components, tuple(speeds))


def _client(scheduler):
    """(Dask client or None, workers, things to close)."""
    if scheduler is None:
        return None, 1, []
    from distributed import Client

    from motoflex_ros.study.runner import local_cluster
    try:
        if scheduler == "local":
            cluster = local_cluster(n_workers=2)
            client = Client(cluster)
            return client, 2, [client, cluster]
        client = Client(scheduler, timeout=10)
    except OSError as exc:
        raise ConfigError(_ARGS, "--scheduler", f"cannot use {scheduler}: {exc}") from None
    return client, max(1, len(client.scheduler_info()["workers"])), [client]


def _print(result, stream):
    def row(name, p):
        check = p.full_check["max_abs_difference"] if p.full_check else float("nan")
        return [name, f"{p.outputs['mass_kg']:.3f}"] + [f"{p.outputs[n]:.4f}" for n in
                                                        result.floors] + [f"{check:.1e}"]
    rows = [row("nominal", result.nominal)]
    if result.lightest is not None:
        rows.append(row("lightest feasible", result.lightest))
    rows += [row(f"pareto {i}", p) for i, p in enumerate(result.pareto)]
    print_table(["design", "mass kg"] + list(result.floors) + ["full check"], rows, stream)
    if result.why_none:
        stream.write(result.why_none + "\n")
    if result.stiffness:
        changes = {**{f"k {c}": v for c, v in result.stiffness["k_static"].items()},
                   **result.stiffness["modal"]}
        stream.write("stiffness change of the lightest feasible design: " + ", ".join(
            f"{f} {'n/a' if v is None else f'{100 * v:+.1f} %'}" for f, v in changes.items())
            + "\n")
    stream.write(f"{result.evaluations} evaluations; " + ", ".join(
        f"{k} {v:.1f} s" for k, v in result.seconds.items()) + "\n")


def run_design(args):
    """``motoflex study design``; returns the exit code."""
    from motoflex_ros.study.design_study import run_design_study

    _check_counts(args)
    if args.seed < 0:
        raise ConfigError(_ARGS, "--seed", f"must be >= 0, got {args.seed}")
    evaluator, full = _setup(args)
    client, workers, to_close = _client(args.scheduler)
    try:
        result = run_design_study(evaluator, full, seed=args.seed, scheduler=client,
                                  workers=workers, pop_size=args.pop_size,
                                  n_gen=args.generations, maxiter=args.maxiter,
                                  max_points=args.max_points)
    finally:
        for thing in to_close:
            thing.close()
    files = write_design_files(result, args.out) if args.out else {}
    if args.plot:
        from motoflex_ros.plots.design_front import plot_design_front, plot_stiffness_changes
        Path(args.plot).mkdir(parents=True, exist_ok=True)
        written = [plot_design_front(result, Path(args.plot) / "design_front.png")]
        if result.stiffness:
            written.append(plot_stiffness_changes(result, Path(args.plot) /
                                                  "design_stiffness.png"))
        if not args.json:
            print("wrote " + ", ".join(str(p) for p in written), file=sys.stderr)
    if args.json:
        emit_json(result.to_dict(files))
    else:
        _print(result, sys.stdout)
    return 0
