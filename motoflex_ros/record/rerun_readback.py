"""Read a saved rerun recording back: rows per entity path, scalar values, the blueprint's
views and the entities they show, CLI verification.

Used by tests and by ``motoflex rerun`` to check what it wrote. rerun-sdk 0.41 has no
``rerun.dataframe``; the recording is read with ``rerun.chunk.RrdReader``.
"""
import shutil
import subprocess
import uuid
from collections import Counter
from dataclasses import dataclass
from pathlib import Path

from rerun.chunk import RrdReader

from motoflex_ros.record.rerun_private import private_rerun_env

__all__ = ["entity_rows", "scalar_values", "component_rows", "verify_text", "rerun_executable",
           "recordings", "BlueprintView", "blueprint_views", "query_entities"]


def recordings(rrd_path):
    """Store entries (kind, application id, recording id) of the recordings in the file."""
    return RrdReader(Path(rrd_path)).recordings()


def entity_rows(rrd_path, static=False):
    """Rows per entity path, {path: rows}: time-stamped rows, or static ones (``static``)."""
    rows = Counter()
    for chunk in RrdReader(Path(rrd_path)).stream().to_chunks():
        if chunk.is_static == static:
            rows[chunk.entity_path] += chunk.num_rows
    return dict(rows)


def scalar_values(rrd_path, entity_path):
    """The Scalars values logged at ``entity_path`` (first value of each row), in row order."""
    values = []
    for chunk in RrdReader(Path(rrd_path)).stream().to_chunks():
        if chunk.entity_path != entity_path:
            continue
        batch = chunk.to_record_batch()
        index = batch.schema.get_field_index("Scalars:scalars")
        if index < 0:       # e.g. the static SeriesLines styling of the same entity
            continue
        values += [row[0] for row in batch.column(index).to_pylist()]
    return values


def component_rows(rrd_path, entity_path, column, timeline=None):
    """Rows of one component column at ``entity_path``, e.g. 'LineStrips3D:strips'.

    Returns [(time, value)] in file order: ``time`` the row's ``timeline`` value (integer
    nanoseconds for a duration timeline, the sequence number otherwise), None for static rows
    or without ``timeline``; ``value`` the row's component batch as plain lists.
    """
    rows = []
    for chunk in RrdReader(Path(rrd_path)).stream().to_chunks():
        if chunk.entity_path != entity_path:
            continue
        batch = chunk.to_record_batch()
        index = batch.schema.get_field_index(column)
        if index < 0:
            continue
        times = [None] * batch.num_rows
        if timeline is not None and not chunk.is_static:
            where = batch.schema.get_field_index(timeline)
            times = batch.column(where).cast("int64").to_pylist()
        rows += zip(times, batch.column(index).to_pylist())
    return rows


def rerun_executable():
    """Path of the rerun CLI binary shipped in rerun-sdk (else ``rerun`` on PATH).

    The binary itself, not the ``bin/rerun`` Python wrapper: the wrapper runs the binary as a
    child and does not pass SIGTERM on, so stopping the wrapper would orphan the viewer.
    """
    try:
        import rerun_cli
    except ImportError:
        return shutil.which("rerun")
    binary = Path(rerun_cli.__file__).with_name("rerun")
    return str(binary) if binary.exists() else shutil.which("rerun")


def verify_text(rrd_path):
    """Output of ``rerun rrd verify``: exit 0 alone is not enough (0 files also exit 0)."""
    rerun = rerun_executable()
    with private_rerun_env(rerun) as env:
        result = subprocess.run([rerun, "rrd", "verify", str(rrd_path)], capture_output=True,
                                text=True, timeout=120, env=env)
    return f"exit {result.returncode}\n{result.stdout}{result.stderr}"


@dataclass(frozen=True)
class BlueprintView:
    """A view of a stored blueprint: class ('TimeSeries', '3D', ...), name, origin, query."""

    kind: str
    name: str
    origin: str
    query: tuple


def _blueprint_fields(rrd_path):
    """{entity path: {column: last value}} of the file's (first) blueprint store."""
    reader = RrdReader(Path(rrd_path))
    fields = {}
    for store in reader.blueprints()[:1]:
        for chunk in reader.stream(store=store).to_chunks():
            batch = chunk.to_record_batch()
            last = fields.setdefault(chunk.entity_path, {})
            for name, column in zip(batch.schema.names, batch.columns):
                values = [v for v in column.to_pylist() if v is not None]
                if ":" in name and values:
                    last[name] = values[-1]
    return fields


def blueprint_views(rrd_path):
    """The views the stored blueprint shows, in layout order: walked from the viewport's root
    container through the containers' contents (views no container holds are not shown)."""
    fields = _blueprint_fields(rrd_path)
    root = fields.get("/viewport", {}).get("ViewportBlueprint:root_container")
    pending = [f"container/{uuid.UUID(bytes=bytes(root[0]))}"] if root else []
    views = []
    while pending:
        item = pending.pop(0)
        entry = fields.get(f"/{item}", {})
        if item.startswith("container/"):
            pending[:0] = entry.get("ContainerBlueprint:contents", [])
            continue
        views.append(BlueprintView(
            entry["ViewBlueprint:class_identifier"][0],
            entry.get("ViewBlueprint:display_name", [""])[0],
            entry["ViewBlueprint:space_origin"][0],
            tuple(fields.get(f"/{item}/ViewContents", {}).get("ViewContents:query",
                                                              ["$origin/**"]))))
    return views


def _rule(expression, origin):
    """(path parts, whole subtree, include) of one query expression ('+ /a/**', '- /a/b')."""
    text = expression.strip()
    include = not text.startswith("-")
    text = text.lstrip("+-").strip().replace("$origin", origin)
    subtree = text == "**" or text.endswith("/**")
    path = text[:-2] if subtree else text
    return tuple(p for p in path.split("/") if p), subtree, include


def query_entities(query, origin, entity_paths):
    """The ``entity_paths`` a view's query expressions select, as rerun evaluates them.

    An expression includes (optional '+') or excludes ('-') one path, or with a trailing
    '/**' the path and its whole subtree; '$origin' is the view's origin. Of the rules that
    match a path the most specific wins (the longer path; at the same path the exact rule),
    among equals the last; a path no rule matches is left out. A '*' elsewhere is a plain
    path part (rerun supports no other wildcard).
    """
    rules = [_rule(line, origin) for expression in query for line in expression.splitlines()
             if line.strip()]
    selected = []
    for path in entity_paths:
        parts = tuple(p for p in path.split("/") if p)
        matches = [((len(rule), not subtree, i), include)
                   for i, (rule, subtree, include) in enumerate(rules)
                   if parts == rule or (subtree and parts[:len(rule)] == rule)]
        if matches and max(matches)[1]:
            selected.append(path)
    return selected
