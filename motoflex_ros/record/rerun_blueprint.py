"""Default layout of a run's recording in the rerun viewer (rerun.blueprint).

Three tabs so the viewer opens ready to read: the bench (3D components with load arrows and
deformation axes beside the load and displacement time series), the identification (identified
values), and the vehicle (road test and modes in 3D, eigenvalues against speed).
"""
import rerun.blueprint as rrb

from motoflex_ros.record.rerun_log import TIMELINE

__all__ = ["default_blueprint"]


def _bench_tab(components):
    series = [rrb.TimeSeriesView(origin=f"/bench/{c}/load/{what}", name=f"{c}: {label}")
              for c in components
              for what, label in (("force", "load [N]"),
                                  ("end_displacement", "loaded-end displacement [m]"))]
    return rrb.Horizontal(
        rrb.Spatial3DView(origin="/bench", name="Bench (3D)"),
        rrb.Vertical(*series) if series else rrb.TimeSeriesView(origin="/bench", name="Bench"),
        column_shares=[3, 2], name="Bench")


def _vehicle_tab():
    return rrb.Horizontal(
        rrb.Vertical(rrb.Spatial3DView(origin="/vehicle", name="Vehicle (3D)",
                                       contents=["/vehicle/road_test/**",
                                                 "/vehicle/joint_axes/**"]),
                     rrb.Spatial3DView(origin="/vehicle/modes", name="Weave and wobble modes")),
        rrb.Vertical(
            rrb.TimeSeriesView(origin="/vehicle/eigenvalues", name="Real part against speed",
                               contents="/vehicle/eigenvalues/*/real_part"),
            rrb.TimeSeriesView(origin="/vehicle/eigenvalues", name="Frequency against speed",
                               contents="/vehicle/eigenvalues/*/frequency_hz"),
            rrb.TimeSeriesView(origin="/vehicle/road_test/joints", name="Road test joints")),
        name="Vehicle")


def default_blueprint(components=()):
    """Blueprint with Bench, Identification and Vehicle tabs; the bench tab is active.

    The blueprint and selection side panels start collapsed to leave the views the room.

    ``components`` names the bench components (one load/displacement plot each). The time
    panel opens on ``sim_time``; eigenvalue plots use ``speed_kmh`` and the modes
    ``mode_frame`` (pick them in the time panel).
    """
    tabs = rrb.Tabs(_bench_tab(tuple(components)),
                    rrb.TimeSeriesView(origin="/identification", name="Identification"),
                    _vehicle_tab(), active_tab=0)
    return rrb.Blueprint(tabs, rrb.BlueprintPanel(state="collapsed"),
                         rrb.SelectionPanel(state="collapsed"),
                         rrb.TimePanel(timeline=TIMELINE, state="expanded"))
