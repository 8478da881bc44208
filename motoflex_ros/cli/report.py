"""``motoflex report bags/<run>``: write bags/<run>/report.html from the run's JSON outputs."""
from pathlib import Path

__all__ = ["register", "run"]


def register(subparsers):
    parser = subparsers.add_parser(
        "report", help="write the run's report.html (tables and figures beside the paper's)",
        description="Write bags/<run>/report.html (self-contained): components and modes, "
                    "Tables 1-2 beside the paper's, Figs. 5-10, the Whipple check and the "
                    "timings, from the verbs' JSON outputs saved in the run folder; missing "
                    "ones are computed and saved unless --no-compute.")
    parser.add_argument("run", type=Path, help="run folder bags/<run>")
    parser.add_argument("--no-compute", dest="compute", action="store_false",
                        help="use only the JSON outputs already in the run folder")
    parser.add_argument("--quiet", action="store_true", help="no progress bars")
    parser.add_argument("--allow-incomplete", action="store_true",
                        help="report a run that failed or did not finish (its status.json is "
                             "not 'complete'); the report says so at the top")
    parser.set_defaults(func=run)


def run(args):
    from motoflex_ros.launcher.status import require_complete
    from motoflex_ros.report.build import build_report
    from motoflex_ros.report.html import Missing
    from motoflex_ros.report.run_folder import run_folder
    folder = run_folder(args.run)
    incomplete = require_complete(folder, args.allow_incomplete)
    path, sections = build_report(folder, compute=args.compute, progress=not args.quiet,
                                  warning=incomplete and f"Incomplete run: {incomplete}")
    missing = [s.title for s in sections if any(isinstance(p, Missing) for p in s.parts)]
    if incomplete:
        print(f"warning: {incomplete}; reported anyway (--allow-incomplete)")
    print(f"wrote {path}")
    if missing:
        print("not available: " + "; ".join(missing))
    return 0
