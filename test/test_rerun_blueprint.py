"""The rerun layout of a converted run: every view of the stored blueprint shows logged rows.

The example campaign bag (bags/example) is converted; the test reads the .rrd back, walks the
blueprint from the viewport through its containers to every view, and evaluates each view's
query expressions over the recording's entity paths as rerun does (issue 16, point 1: the
eigenvalue views queried '/vehicle/eigenvalues/*/real_part', which matches nothing).
"""
from pathlib import Path

import pytest

from motoflex_ros.record.rerun_log import IDENTIFIED_QUANTITIES, quantity_of
from motoflex_ros.record.rerun_readback import blueprint_views, entity_rows, query_entities

EXAMPLE_BAG = Path(__file__).resolve().parents[1] / "bags" / "example"


@pytest.fixture(scope="module")
def recording(tmp_path_factory):
    from motoflex_ros.cli.recording import write_recording
    if not (EXAMPLE_BAG / "metadata.yaml").is_file():
        pytest.skip("bags/example is not in this checkout")
    rrd, _ = write_recording(EXAMPLE_BAG, tmp_path_factory.mktemp("rrd") / "example.rrd")
    temporal, static = entity_rows(rrd), entity_rows(rrd, static=True)
    return blueprint_views(rrd), temporal, static


def _shown(view, temporal, static):
    """The view's entities with rows: time-stamped ones for a plot, any for a 3D view."""
    entities = query_entities(view.query, view.origin, set(temporal) | set(static))
    if view.kind == "TimeSeries":
        return [e for e in entities if temporal.get(e)]
    return [e for e in entities if temporal.get(e) or static.get(e)]


def test_every_blueprint_view_resolves_to_entities_with_rows(recording):
    views, temporal, static = recording
    assert len(views) > 10
    empty = [view.name for view in views if not _shown(view, temporal, static)]
    assert not empty, f"views without data: {empty}"


def test_identification_one_view_per_component_and_quantity_with_units(recording):
    views, temporal, static = recording
    logged = {}
    for path in temporal:
        parts = path.strip("/").split("/")
        if parts[0] == "identification" and quantity_of(parts[-1]):
            logged.setdefault((parts[1], quantity_of(parts[-1])), set()).add(path)
    assert {c for c, _ in logged} == {"frame", "front_assembly", "swingarm"}
    shown = {view.name: set(_shown(view, temporal, static))
             for view in views if view.origin.startswith("/identification")}
    expected = {f"{c}: {q} [{IDENTIFIED_QUANTITIES[q]}]": paths
                for (c, q), paths in logged.items()}
    assert shown == expected


def test_eigenvalue_views_plot_the_tracked_modes(recording):
    views, temporal, static = recording
    by_name = {view.name: view for view in views}
    for what, name in (("real_part", "Real part against speed [1/s]"),
                       ("frequency_hz", "Frequency against speed [Hz]")):
        assert set(_shown(by_name[name], temporal, static)) == {
            f"/vehicle/eigenvalues/{mode}/{what}" for mode in ("weave", "wobble", "capsize")}


def test_query_entities_as_rerun_documents():
    # https://rerun.io/docs/reference/entity-queries: the most specific rule wins, at the same
    # specificity the last; '/**' is the whole subtree; no other wildcard
    query = ["+ /world/**", "- /world", "- /world/car/**", "+ /world/car/driver"]
    paths = ["/world", "/world/car/driver", "/world/car/hood", "/world/house", "/sky"]
    assert query_entities(query, "/", paths) == ["/world/car/driver", "/world/house"]
    assert query_entities(["$origin/**"], "/world/car", paths) == ["/world/car/driver",
                                                                 "/world/car/hood"]
    assert query_entities(["/vehicle/eigenvalues/*/real_part"], "/",
                          ["/vehicle/eigenvalues/weave/real_part"]) == []
