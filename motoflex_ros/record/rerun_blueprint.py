"""Default layout of a run's recording in the rerun viewer (rerun.blueprint).

Three tabs so the viewer opens ready to read: the bench (3D components with load arrows and
deformation axes beside the load and displacement time series), the identification (one plot
per component and quantity, with its unit), and the vehicle (road test and modes in 3D,
eigenvalues against speed).

The layout is built from the entity paths the recording logged, so every view it holds shows
data. A view names its entities exactly or with a trailing ``/**`` (the subtree): rerun
supports no other wildcard, a ``*`` inside a path matches only an entity named ``*``.
"""
import rerun.blueprint as rrb

from motoflex_ros.record.rerun_log import IDENTIFIED_QUANTITIES, TIMELINE, quantity_of

__all__ = ["default_blueprint"]


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
    series = [rrb.TimeSeriesView(origin=f"/bench/{c}/load/{what}", name=f"{c}: {label}")
              for c in components
              for what, label in (("force", "load [N]"),
                                  ("end_displacement", "loaded-end displacement [m]"))
              if f"/bench/{c}/load/{what}" in paths]
    scene = rrb.Spatial3DView(origin="/bench", name="Bench (3D)")
    if not series:
        return rrb.Horizontal(scene, name="Bench")
    return rrb.Horizontal(scene, rrb.Vertical(*series), column_shares=[3, 2], name="Bench")


def _identification_views(paths, component):
    """One time-series view per identified quantity of ``component`` (its tests' values)."""
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
                         if len(_parts(p)) == 4})
    grids = [rrb.Grid(*views, name=c)
             for c in components if (views := _identification_views(paths, c))]
    return rrb.Tabs(*grids, name="Identification") if grids else None


def _eigenvalue_view(paths, what, name):
    contents = [p for p in _under(paths, "/vehicle/eigenvalues")
                if len(_parts(p)) == 4 and _parts(p)[3] == what]
    return rrb.TimeSeriesView(origin="/vehicle/eigenvalues", name=name, contents=contents) \
        if contents else None


def _vehicle_tab(paths):
    scene = [f"{prefix}/**" for prefix in ("/vehicle/road_test", "/vehicle/joint_axes")
             if _under(paths, prefix)]
    spatial = [rrb.Spatial3DView(origin="/vehicle", name="Vehicle (3D)", contents=scene)
               if scene else None,
               rrb.Spatial3DView(origin="/vehicle/modes", name="Weave and wobble modes")
               if _under(paths, "/vehicle/modes") else None]
    plots = [_eigenvalue_view(paths, "real_part", "Real part against speed [1/s]"),
             _eigenvalue_view(paths, "frequency_hz", "Frequency against speed [Hz]"),
             rrb.TimeSeriesView(origin="/vehicle/road_test/joints", name="Road test joints")
             if _under(paths, "/vehicle/road_test/joints") else None]
    columns = [rrb.Vertical(*views) for views in ([v for v in spatial if v],
                                                  [v for v in plots if v]) if views]
    return rrb.Horizontal(*columns, name="Vehicle") if columns else None


def default_blueprint(entity_paths):
    """Blueprint with Bench, Identification and Vehicle tabs for the logged ``entity_paths``.

    A view is there only when the paths give it data; a tab without views is left out. The
    bench tab is active; the blueprint and selection side panels start collapsed to leave the
    views the room. The time panel opens on ``sim_time``; eigenvalue plots use ``speed_kmh``
    and the modes ``mode_frame`` (pick them in the time panel).
    """
    paths = set(entity_paths)
    tabs = [tab for tab in (_bench_tab(paths), _identification_tab(paths), _vehicle_tab(paths))
            if tab is not None]
    return rrb.Blueprint(rrb.Tabs(*tabs, active_tab=0), rrb.BlueprintPanel(state="collapsed"),
                         rrb.SelectionPanel(state="collapsed"),
                         rrb.TimePanel(timeline=TIMELINE, state="expanded"))
