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
                             "not 'complete', or its files are missing or inconsistent); the "
                             "report says so at the top, and shows only what the run recorded")
    parser.set_defaults(func=run)


def run(args):
    from motoflex_ros.launcher.status import IncompleteRun, require_complete
    from motoflex_ros.report.build import build_report
    from motoflex_ros.report.html import Missing
    from motoflex_ros.report.run_folder import run_folder, run_problems
    folder = run_folder(args.run)
    incomplete = require_complete(folder, args.allow_incomplete)
    problems = run_problems(folder)   # a status edited to "complete" does not make a run
    if problems and not args.allow_incomplete:
        raise IncompleteRun(f"{folder}: the run's files are missing or inconsistent: "
                            f"{problems[0]}; its results cannot be trusted. Pass "
                            f"--allow-incomplete to report what it recorded anyway")
    if problems:
        incomplete = "; ".join(filter(None, [incomplete, f"{folder}: the run's files are "
                                                         f"missing or inconsistent: "
                                                         + "; ".join(problems)]))
    path, sections = build_report(folder, compute=args.compute, progress=not args.quiet,
                                  warning=incomplete and f"Incomplete run: {incomplete}")
    missing = [s.title for s in sections if any(isinstance(p, Missing) for p in s.parts)]
    if incomplete:
        print(f"warning: {incomplete}; reported anyway (--allow-incomplete)")
    print(f"wrote {path}")
    if missing:
        print("not available: " + "; ".join(missing))
    return 0
