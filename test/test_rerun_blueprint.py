"""The rerun layout of a converted run: every view of the stored blueprint shows logged rows.

The identification is a table per component, the speed views bar charts over km/h (issue 24).

The example campaign bag (bags/example) is converted; the test reads the .rrd back, walks the
blueprint from the viewport through its containers to every view, and evaluates each view's
query expressions over the recording's entity paths as rerun does (issue 16, point 1: the
eigenvalue views queried '/vehicle/eigenvalues/*/real_part', which matches nothing).
"""
from pathlib import Path

import numpy as np
import pytest
from example_runs import example_recording

from motoflex_ros.record.rerun_readback import (
    blueprint_views,
    entity_rows,
    query_entities,
    scalar_values,
)

EXAMPLE_BAG = Path(__file__).resolve().parents[1] / "bags" / "example"


@pytest.fixture(scope="module")
def recording():
    rrd = example_recording() / "example.rrd"
    temporal, static = entity_rows(rrd), entity_rows(rrd, static=True)
    return blueprint_views(rrd), temporal, static, rrd


def _shown(view, temporal, static):
    """The view's entities with rows: time-stamped ones for a plot, any for a 3D view."""
    entities = query_entities(view.query, view.origin, set(temporal) | set(static))
    if view.kind == "TimeSeries":
        return [e for e in entities if temporal.get(e)]
    return [e for e in entities if temporal.get(e) or static.get(e)]


def test_every_blueprint_view_resolves_to_entities_with_rows(recording):
    views, temporal, static, _ = recording
    assert len(views) > 10
    empty = [view.name for view in views if not _shown(view, temporal, static)]
    assert not empty, f"views without data: {empty}"


def test_identification_one_table_per_component_in_units(recording):
    """Issue 24, point 6: the identified values as a table per component (one view each, on
    any timeline), every value of the run's identification.json in it, beta in degrees and the
    static c marked assumed (they were one dot each on a time axis, beta in rad)."""
    import json

    from motoflex_ros.record.rerun_readback import component_rows
    views, temporal, static, _ = recording
    shown = {view.name: (view.kind, _shown(view, temporal, static))
             for view in views if view.origin.startswith("/identification")}
    assert shown == {f"{c}: identified values": ("TextDocument", [f"/identification/{c}/table"])
                     for c in ("frame", "front_assembly", "swingarm")}
    identified = json.loads((EXAMPLE_BAG / "identification.json").read_text())
    rrd = recording[3]
    for c, result in identified.items():
        # the last of the table's static rows is what the viewer shows (the run's file's)
        text = component_rows(rrd, f"/identification/{c}/table", "TextDocument:text")[-1][1][0]
        rows = {line.split("|")[1].strip(): [cell.strip() for cell in line.split("|")[2:-1]]
                for line in text.splitlines() if line.startswith("| ")}
        assert rows["test"][1] == "\u03b2 [deg]"
        for test in ("static", "torsion", "bending"):
            assert float(rows[test][1]) == pytest.approx(np.degrees(result[test]["beta"]),
                                                         abs=0.006)
            assert float(rows[test][3]) == pytest.approx(result[test]["k"], rel=1e-3)
        assert rows["static"][4].endswith("(assumed)")
        assert f"k_t = {result['k_t']:.4g}" in text and f"k_b = {result['k_b']:.4g}" in text


def test_stability_bars_are_the_tracked_modes_over_speed(recording):
    """The vehicle's speed views are bar charts over km/h (static: the timeline the viewer
    opens on shows them), weave and wobble each in its colour, equal to the bag's
    eigenvalues."""
    from motoflex_ros.record.rerun_readback import component_rows
    from motoflex_ros.record.rerun_vehicle import MODE_COLORS
    views, temporal, static, _ = recording
    bars = {view.name: _shown(view, temporal, static) for view in views
            if view.kind == "BarChart"}
    assert bars == {f"{m} {label} / km/h": [f"/vehicle/stability/{m}/{q}"]
                    for q, label in (("real_part", "Re [1/s]"), ("frequency_hz", "f [Hz]"))
                    for m in ("weave", "wobble")}
    rrd = recording[3]
    for mode in ("weave", "wobble"):
        real = scalar_values(rrd, f"/vehicle/eigenvalues/{mode}/real_part")
        values = component_rows(rrd, f"/vehicle/stability/{mode}/real_part",
                                "BarChart:values")[-1][1]
        np.testing.assert_allclose(values[0]["buffer"], np.nan_to_num(real), rtol=1e-12)
        color = component_rows(rrd, f"/vehicle/stability/{mode}/real_part",
                               "BarChart:color")[-1][1]
        assert color[0] >> 8 == (MODE_COLORS[mode][0] << 16) + (MODE_COLORS[mode][1] << 8) \
            + MODE_COLORS[mode][2]


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
