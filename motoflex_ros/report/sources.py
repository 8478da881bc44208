"""The data a report is made from: the JSON outputs of the motoflex verbs, per run folder.

Each source is one verb's ``--json`` output saved in the run folder under a fixed file name
(``motoflex campaign`` writes them; ``motoflex report`` computes the missing ones on demand by
running the verb and saves what it got, so the report can always be traced to its JSON).
A source that is neither saved nor computable is "not available" with the reason.
"""
import json
import subprocess
import sys
import time
from dataclasses import dataclass, field

from motoflex_ros.files import atomic_write_text, read_json
from motoflex_ros.formats.json_yaml import json_text
from motoflex_ros.launcher.campaign_graph import VEHICLE_COMPONENTS, VEHICLE_VARIANT
from motoflex_ros.progress import progress_bar
from motoflex_ros.report.run_folder import RUN_RESULT, is_recorded_run

__all__ = ["Source", "SOURCES", "RunData", "load_run_data", "FIG9_VARIANTS"]

SWEEP = ["--range-kmh", "40", "210", "--step-kmh", "10"]
IDENTIFIED = "{identified}"     # replaced by the run's identification file (dropped if none)
IDENTIFICATION_FILES = ("identification.json", "identify.json")
FIG9_VARIANTS = ("flexible", "state_of_the_art", "static", "torsion", "bending")


@dataclass(frozen=True)
class Source:
    """One verb output: name, file in the run folder, verb arguments (without --json), and
    other file names the same JSON may have (the campaign writes identification.json);
    ``computable`` False: never run on demand (minutes of work: the design study), only read
    when saved."""

    name: str
    file: str
    args: tuple
    aliases: tuple = ()
    computable: bool = True


SOURCES = (
    Source("components", "components.json", ("components",)),
    Source("identify", "identify.json", ("identify",), ("identification.json",)),
    # the motorcycle the campaign prints: its vehicle_simulator's variant of the identified values
    Source("eig", "eig.json", ("eig", "--vehicle", "touring", "--flex", VEHICLE_VARIANT,
                               *(a for c in VEHICLE_COMPONENTS for a in ("--component", c)),
                               "--identified", IDENTIFIED, *SWEEP)),
    Source("accuracy", "accuracy.json", ("study", "accuracy", "--identified", IDENTIFIED)),
    Source("sensitivity", "sensitivity.json", ("study", "sensitivity", "--identified",
                                               IDENTIFIED)),
    Source("whipple", "whipple.json", ("eig", "--vehicle", "whipple_benchmark", "--speeds-ms", "5",
                                       "10")),
    Source("design", "design.json", ("study", "design"), computable=False),
    *(Source(f"fig9_{v}", f"eig_front_assembly_{v}.json",
             ("eig", "--vehicle", "touring", "--flex", v, "--component", "front_assembly",
              "--identified", IDENTIFIED, *SWEEP)) for v in FIG9_VARIANTS),
)


@dataclass
class RunData:
    """Loaded sources: ``data`` {name: JSON}, ``missing`` {name: reason}, ``timings``
    [(step, seconds)] of this report's own steps, ``campaign_timings`` from timings.json,
    ``origins`` {name: where it came from}, ``files`` {name: JSON file in the run folder}."""

    data: dict = field(default_factory=dict)
    missing: dict = field(default_factory=dict)
    timings: list = field(default_factory=list)
    campaign_timings: dict = field(default_factory=dict)
    origins: dict = field(default_factory=dict)
    files: dict = field(default_factory=dict)


def _read(path):
    try:
        return read_json(path), None
    except (OSError, ValueError) as exc:
        return None, f"{path.name} unreadable ({exc})"


def _arguments(folder, args):
    """The verb's arguments with the run's identification file in place of IDENTIFIED."""
    found = [folder / n for n in IDENTIFICATION_FILES if (folder / n).is_file()]
    out = []
    for arg in args:
        if arg == IDENTIFIED:
            if found:
                out.append(str(found[0]))
            else:
                out.pop()       # no file: drop the option, the verb uses its default
        else:
            out.append(arg)
    return out


def _compute(folder, source):
    """Run ``motoflex ARGS --json``; (data, None) or (None, reason)."""
    cmd = [sys.executable, "-m", "motoflex_ros.cli.main", *_arguments(folder, source.args),
           "--json"]
    result = subprocess.run(cmd, capture_output=True, text=True)
    if result.returncode != 0:
        lines = (result.stderr or result.stdout).strip().splitlines()
        return None, (lines[-1] if lines else f"exit code {result.returncode}")
    try:
        return json.loads(result.stdout), None
    except json.JSONDecodeError as exc:
        return None, f"'{' '.join(cmd[3:])}' printed no JSON ({exc})"


def _save(folder, source, data):
    atomic_write_text(folder / source.file, json_text(data))


def _not_the_runs(folder, source):
    """Why ``source`` may not be computed for ``folder`` (None if it may): a recorded run
    without its own identification.json gets no identification made up offline, neither the
    identification itself nor anything built of it (issue 23, point 8)."""
    uses_identification = source.name == "identify" or IDENTIFIED in source.args
    if uses_identification and is_recorded_run(folder) and not (folder / RUN_RESULT).is_file():
        return (f"the run recorded no {RUN_RESULT}; an identification computed now would not "
                f"be the run's (not computed)")
    return None


def _load_one(folder, source, compute, run):
    refused = _not_the_runs(folder, source)
    if refused:
        run.missing[source.name] = refused
        run.files[source.name] = source.file
        return
    saved = [folder / n for n in (source.file, *source.aliases) if (folder / n).is_file()]
    run.files[source.name] = saved[0].name if saved else source.file
    if saved:
        data, reason = _read(saved[0])
        origin = f"{saved[0].name} (saved)"
    elif compute and source.computable:
        data, reason = _compute(folder, source)
        origin = (f"motoflex {' '.join(_arguments(folder, source.args))} --json (computed now, "
                  f"saved as {source.file})")
        if data is not None:
            _save(folder, source, data)
    else:
        why = "--no-compute" if source.computable else f"motoflex {' '.join(source.args)} " \
            f"--json > {source.file} writes it"
        data, reason = None, f"{source.file} not in the run folder (not computed: {why})"
        origin = None
    if data is None:
        run.missing[source.name] = reason
    else:
        run.data[source.name] = data
        run.origins[source.name] = origin


def load_run_data(folder, compute=True, progress=True):
    """Load (or compute and save) every source of the report for the run folder ``folder``."""
    run = RunData()
    timings_path = folder / "timings.json"
    if timings_path.is_file():
        run.campaign_timings, _ = _read(timings_path)
        run.campaign_timings = run.campaign_timings or {}
    bar = progress_bar(SOURCES, desc="report data", unit="source", enabled=progress)
    for source in bar:
        bar.set_postfix_str(source.name)
        start = time.perf_counter()
        _load_one(folder, source, compute, run)
        run.timings.append((f"data: {source.name}", time.perf_counter() - start))
    return run
