"""Default layout of a run's recording in the rerun viewer (rerun.blueprint).

Three tabs so the viewer opens ready to read, every view showing data with its units on the
timeline it opens on (``sim_time``): the bench (3D components with load arrows, deformation
axes and names beside one tab per component of its load and loaded-end displacement against
time), the identification (one table per component: every test's l, beta in degrees, b, k, c,
J, f and the eq. 12 split), and the vehicle (the road test in 3D followed by the camera, weave
and wobble animated side by side in their colours and labelled, and bar charts of each mode's
real part and frequency over speed in km/h, static so any timeline shows them).

The layout is built from the entity paths the recording logged, so every view it holds shows
data. A view names its entities exactly or with a trailing ``/**`` (the subtree): rerun
supports no other wildcard, a ``*`` inside a path matches only an entity named ``*``.
"""
import rerun.blueprint as rrb

from motoflex_ros.record.rerun_log import IDENTIFIED_QUANTITIES, TIMELINE, quantity_of
from motoflex_ros.record.rerun_motorcycle import MODE_SPACING_M
from motoflex_ros.record.rerun_vehicle import STABILITY_QUANTITIES
from motoflex_ros.vehicle.mode_names import STUDIED_MODES

__all__ = ["default_blueprint", "default_tabs", "viewer_panels", "tab_views", "TRACKED_BODY"]

TRACKED_BODY = "frame"
"""The road test's body the 3D vehicle view's camera follows."""


def _parts(path):
    return [p for p in path.split("/") if p]


def _under(paths, prefix):
    """The logged paths in the subtree of ``prefix`` (itself included)."""
    head = _parts(prefix)
    return sorted(p for p in paths if _parts(p)[:len(head)] == head)


def _bench_tab(paths):
    if not _under(paths, "/bench"):
        return None
    components = sorted({_parts(p)[1] for p in _under(paths, "/bench")
                         if _parts(p)[2:] == ["load", "force"]})
    pages = []
    for c in components:
        series = [rrb.TimeSeriesView(origin=f"/bench/{c}/load/{what}", name=f"{c}: {label}")
                  for what, label in (("force", "load [N]"),
                                      ("end_displacement", "loaded-end displacement [m]"))
                  if f"/bench/{c}/load/{what}" in paths]
        if series:
            pages.append(rrb.Vertical(*series, name=c))
    scene = rrb.Spatial3DView(origin="/bench", name="Bench (3D)")
    if not pages:
        return rrb.Horizontal(scene, name="Bench")
    # one component's two plots at a time: tall enough for their ticks to read
    return rrb.Horizontal(scene, rrb.Tabs(*pages), column_shares=[3, 2], name="Bench")


def _identification_views(paths, component):
    """The component's table, or (a recording without one) a time-series view per identified
    quantity."""
    if f"/identification/{component}/table" in paths:
        return [rrb.TextDocumentView(origin=f"/identification/{component}/table",
                                     name=f"{component}: identified values")]
    logged = [p for p in _under(paths, f"/identification/{component}") if len(_parts(p)) == 4]
    views = []
    for quantity, unit in IDENTIFIED_QUANTITIES.items():
        contents = [p for p in logged if quantity_of(_parts(p)[3]) == quantity]
        if contents:
            views.append(rrb.TimeSeriesView(origin=f"/identification/{component}",
                                            name=f"{component}: {quantity} [{unit}]",
                                            contents=contents))
    return views


def _identification_tab(paths):
    components = sorted({_parts(p)[1] for p in _under(paths, "/identification")
                         if len(_parts(p)) >= 3})
    views = [v for c in components for v in _identification_views(paths, c)]
    if not views:
        return None
    tables = all(isinstance(v, rrb.TextDocumentView) for v in views)
    # the tables one above the other, each the tab's full width: every column shows
    return (rrb.Vertical if tables else rrb.Grid)(*views, name="Identification")


def _stability_views(paths):
    """Bar charts of each mode's real part and frequency over speed [km/h]."""
    modes = [m for m in STUDIED_MODES
             if f"/vehicle/stability/{m}/real_part" in paths]
    return [rrb.BarChartView(origin=f"/vehicle/stability/{m}/{q}",
                             name=f"{m} {label} / km/h",
                             plot_legend=rrb.PlotLegend(visible=False))
            for q, label in STABILITY_QUANTITIES.items() for m in modes
            if f"/vehicle/stability/{m}/{q}" in paths]


def _vehicle_tab(paths):
    road = [p for p in _under(paths, "/vehicle/road_test")
            if _parts(p)[2:3] != ["joints"] and p != "/vehicle/road_test"]
    tracked = f"/vehicle/road_test/{TRACKED_BODY}"
    eye = rrb.EyeControls3D(tracking_entity=tracked) if tracked in paths else None
    # the identified joint axes stand at the motorcycle's rest position: with the modes
    modes = [f"{prefix}/**" for prefix in ("/vehicle/modes", "/vehicle/joint_axes")
             if _under(paths, prefix)]
    spatial = [rrb.Spatial3DView(origin="/vehicle/road_test", name="Road test (3D), the "
                                 "camera following the motorcycle", contents=road,
                                 eye_controls=eye) if road else None,
               rrb.Spatial3DView(origin="/vehicle", contents=modes, name="Weave (blue) and "
                                 "wobble (red), exaggerated; identified joint axes",
                                 eye_controls=rrb.EyeControls3D(
                                     position=(MODE_SPACING_M / 2 + 0.7, -5.0, 1.5),
                                     look_target=(MODE_SPACING_M / 2 + 0.7, 0.0, 0.6),
                                     eye_up=(0.0, 0.0, 1.0)))
               if _under(paths, "/vehicle/modes") else None]
    bars = _stability_views(paths)
    plots = [rrb.Grid(*bars, grid_columns=2)] if bars else []
    if _under(paths, "/vehicle/road_test/joints"):
        plots.append(rrb.TimeSeriesView(origin="/vehicle/road_test/joints",
                                        name="Road test joints [rad or m] against time"))
    columns = [rrb.Vertical(*views) for views in ([v for v in spatial if v], plots) if views]
    return rrb.Horizontal(*columns, name="Vehicle") if columns else None


def default_blueprint(entity_paths, active_tab=0):
    """Blueprint with Bench, Identification and Vehicle tabs for the logged ``entity_paths``.

    A view is there only when the paths give it data; a tab without views is left out. Tab
    ``active_tab`` (default the bench) is active; the blueprint and selection side panels
    start collapsed to leave the views the room. The time panel opens on ``sim_time``, on
    which every view shows data (the modes are animated over it too; the speed bar charts and
    tables are static).
    """
    return rrb.Blueprint(rrb.Tabs(*default_tabs(entity_paths), active_tab=active_tab),
                         *viewer_panels())


def default_tabs(entity_paths):
    """The tabs (rerun containers) of :func:`default_blueprint`: Bench, Identification,
    Vehicle, those with data."""
    paths = set(entity_paths)
    return [tab for tab in (_bench_tab(paths), _identification_tab(paths), _vehicle_tab(paths))
            if tab is not None]


def viewer_panels():
    """The side panels collapsed and the time panel expanded on ``sim_time``: the timeline
    the viewer opens on."""
    return (rrb.BlueprintPanel(state="collapsed"), rrb.SelectionPanel(state="collapsed"),
            rrb.TimePanel(timeline=TIMELINE, state="expanded"))


def tab_views(tab):
    """Every view inside the container ``tab``, depth first."""
    if isinstance(tab, rrb.View):
        return [tab]
    return [v for part in tab.contents for v in tab_views(part)]
