"""Recompute the regression values of test/regression_values.json (test/regression.py says what
they are): numbers the suite pins that our own code produced.

    python tools/regenerate_regression_values.py              # all groups: old, new, within?
    python tools/regenerate_regression_values.py bracket      # one group (they take minutes)
    python tools/regenerate_regression_values.py --write      # rewrite the changed values

Each value is computed the way its test gets it: the same CLI verb (run in this process) or
the same test helper. --write stores a changed value with the current commit (``git rev-parse
--short HEAD``; commit the code change first) and keeps the tolerance; an unchanged value
keeps its commit. Exit 1 when a value left its tolerance (without --write).
"""
import argparse
import contextlib
import io
import json
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "test"))

from regression import FILE, entries, expected  # noqa: E402  (test/ on the path first)


def _cli_json(*argv):
    """The --json document of ``motoflex argv`` run in this process."""
    from motoflex_ros.cli.main import main
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        code = main([str(a) for a in argv])
    if code:
        raise SystemExit(f"motoflex {' '.join(map(str, argv))}: exit {code}")
    return json.loads(out.getvalue())


def bracket():
    """The L-bracket mesh's identified torsion and bending frequencies [Hz] (test_mesh_chain)."""
    from motoflex_ros.formats.mesh_examples import write_bracket_component
    with tempfile.TemporaryDirectory() as folder:
        path = write_bracket_component(Path(folder) / "bracket")
        found = _cli_json("identify", "--component", path, "--noise", "0", "--json")["bracket"]
    return {f"bracket.{label}_f_hz": found[label]["f_hz"] for label in ("torsion", "bending")}


def flexible_sensitivity():
    """The swingarm torsion's low-speed weave correlation, lumped and flexible
    (test_study_flexible_sensitivity)."""
    data = _cli_json("study", "sensitivity", "--model", "flexible", "--identified",
                     ROOT / "bags/example/identification.json", "--step-kmh", "10", "--json")
    k_ts = data["agreement"]["weave_low"]["k_ts"]
    return {f"flexible_sensitivity.weave_low.k_ts.{m}": k_ts[m] for m in ("lumped", "flexible")}


def swingarm_yaw_share():
    """The swingarm hinges' yaw compliance at the axle over the FE's (test_study_accuracy)."""
    from test_study_accuracy import identified_components, swingarm_hinge_compliances
    fe, hinges = swingarm_hinge_compliances(identified_components()["swingarm"])
    return {f"swingarm_yaw_share.{t}": float(h[5, 5] / fe[5, 5]) for t, h in hinges.items()}


GROUPS = {"bracket": bracket, "flexible_sensitivity": flexible_sensitivity,
          "swingarm_yaw_share": swingarm_yaw_share}


def _commit():
    return subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, check=True,
                          capture_output=True, text=True).stdout.strip()


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("groups", nargs="*", metavar="GROUP",
                        help=f"groups to recompute: {', '.join(GROUPS)} (default: all)")
    parser.add_argument("--write", action="store_true", help="rewrite the changed values")
    args = parser.parse_args(argv)
    unknown = set(args.groups) - set(GROUPS)
    if unknown:
        parser.error(f"unknown group {sorted(unknown)}; choose from {', '.join(GROUPS)}")
    table = entries()
    missing = {key.split(".", 1)[0] for key in table} - set(GROUPS)
    if missing:
        raise SystemExit(f"{FILE}: no way to recompute {sorted(missing)}")
    outside = []
    for group in args.groups or list(GROUPS):
        for key, value in GROUPS[group]().items():
            within = value == expected(key)
            print(f"{key}: pinned {table[key]['value']:.6g} ({table[key]['commit']}), "
                  f"now {value:.6g}{'' if within else '  OUTSIDE the tolerance'}")
            stored = float(f"{value:.6g}")   # six digits: more than any tolerance reads
            if args.write and stored != table[key]["value"]:
                table[key].update(value=stored, commit=_commit())
            elif not within:
                outside.append(key)
    if args.write:
        FILE.write_text(json.dumps(table, indent=2, sort_keys=True) + "\n", encoding="utf-8")
    return 1 if outside else 0


if __name__ == "__main__":
    sys.exit(main())
