"""Figures of the report as PNG bytes (matplotlib, Agg): components with their modes, the
deformation axes of Figs. 5-7, the front-assembly curves of Fig. 9, and Figs. 8 and 10 through
:mod:`motoflex_ros.plots.study_figures`. Imported lazily by ``motoflex report``.
"""
import functools
import io

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from motoflex_ros.formats.component_file import load_component
from motoflex_ros.plots.axes import axes_figure as component_axes_figure
from motoflex_ros.plots.component_figure import mode_drawing
from motoflex_ros.plots.labels import VARIANT_LABELS  # noqa: E402
from motoflex_ros.plots.study_figures import accuracy_bars_figure, pearson_bars_figure
from motoflex_ros.units import ms_to_kmh  # noqa: E402
from motoflex_ros.vehicle.mode_names import STUDIED_MODES

__all__ = ["png_of", "component_modes_figure", "axes_figure", "fig9_figure", "fig8_figure",
           "fig10_figure", "component_model", "modes_plot", "DPI"]

CLAMP = "#5ac8ff"
LOAD = "#ff8c00"
MODE_COLORS = {"torsion": "#2ca02c", "bending": "#d62728"}
MODE_STYLES = {"torsion": "-", "bending": "--"}
DPI = 100
MODE_PANEL_WIDTH_IN = 8.8   # the two views of a mode figure together [in]
MODE_PANEL_MAX_IN = 4.0     # their common height at most [in]


def png_of(fig):
    """PNG bytes of a matplotlib figure at :data:`DPI` (closed afterwards)."""
    buffer = io.BytesIO()
    try:
        fig.savefig(buffer, format="png", dpi=DPI)
    finally:
        plt.close(fig)
    return buffer.getvalue()


@functools.cache
def component_model(name):
    """(Component, ReducedComponent) of a shipped component (built once per process)."""
    component = load_component(name)
    return component, component.clamped_reduced()


def _draw_beams(ax, xyz, elements, dims, **style):
    for i, j in elements:
        ax.plot(xyz[[i, j], dims[0]], xyz[[i, j], dims[1]], **style)


def modes_plot(name):
    """Side (x-z) and top (x-y) views of a component with its first torsion and bending modes
    (matplotlib Figure); each mode's legend entry states its scale factor
    (:func:`motoflex_ros.plots.component_figure.mode_drawing`)."""
    component, reduced = component_model(name)
    xyz, elements = component.node_xyz, component.elements
    modes = [m for m in (mode_drawing(component, reduced, label)
                         for label in MODE_COLORS) if m is not None]
    views = ((0, 2), (0, 1))
    drawn = np.vstack([xyz, *(m.xyz for m in modes)])
    spans = [np.ptp(drawn[:, list(d)], axis=0) * 1.1 + 0.02 for d in views]
    # each view as wide as its data at one common height: no blank band around either plot
    height = min(MODE_PANEL_MAX_IN, MODE_PANEL_WIDTH_IN / sum(sx / sy for sx, sy in spans))
    fig, axes = plt.subplots(
        1, 2, figsize=(MODE_PANEL_WIDTH_IN + 1.8, height + 1.5), layout="constrained",
        gridspec_kw={"width_ratios": [sx / sy for sx, sy in spans]})
    for ax, dims, title in zip(axes, views, ("side (x-z)", "top (x-y)")):
        _draw_beams(ax, xyz, elements, dims, color="0.6", lw=1.5)
        for mode in modes:
            _draw_beams(ax, mode.xyz, elements, dims, color=MODE_COLORS[mode.label], lw=1.0,
                        ls=MODE_STYLES[mode.label])
        ax.plot(*component.clamp_xyz[:, dims].T, "o", color=CLAMP)
        ax.plot(*component.q0[list(dims)], "o", color=LOAD)
        ax.set_aspect("equal", adjustable="datalim")
        ax.set_title(f"{name}: {title}")
        ax.set_xlabel("x [m]")
        ax.set_ylabel("z [m]" if dims[1] == 2 else "y [m]")
    handles = [matplotlib.lines.Line2D([], [], color="0.6", lw=1.5, label="undeformed")]
    handles += [matplotlib.lines.Line2D([], [], color=MODE_COLORS[m.label],
                                        ls=MODE_STYLES[m.label], label=m.legend())
                for m in modes]
    fig.legend(handles=handles, loc="outside upper center", ncols=len(handles), fontsize=9)
    return fig


def component_modes_figure(name):
    """PNG of :func:`modes_plot`."""
    return png_of(modes_plot(name))


def axes_figure(name, identified):
    """Figs. 5-7: PNG of :func:`motoflex_ros.plots.axes.axes_figure`, the figure
    ``motoflex identify --plot`` writes."""
    return png_of(component_axes_figure(component_model(name)[0], identified))


def _mode_curve(eig, mode):
    speeds = ms_to_kmh(eig["speeds_mps"])
    pairs = [(np.nan, np.nan) if z is None else z for z in eig["modes"][mode]]
    values = np.array(pairs, float)
    return speeds, values[:, 0], values[:, 1] / (2 * np.pi)


def fig9_figure(variants):
    """Fig. 9: weave and wobble frequency and real part against speed, front assembly flexible
    only, per model variant (``variants``: {variant: eig JSON})."""
    fig, axes = plt.subplots(2, 2, figsize=(10, 7), sharex=True)
    for col, mode in enumerate(STUDIED_MODES):
        for variant, eig in variants.items():
            speeds, real, freq = _mode_curve(eig, mode)
            style = {"lw": 2.5, "color": "black"} if variant == "flexible" else {"lw": 1.2}
            label = VARIANT_LABELS.get(variant, variant)
            axes[0, col].plot(speeds, freq, label=label, **style)
            axes[1, col].plot(speeds, real, label=label, **style)
        axes[0, col].set_title(mode)
        axes[0, col].set_ylabel("frequency [Hz]")
        axes[1, col].set_ylabel("real part [1/s]")
        axes[1, col].set_xlabel("speed [km/h]")
    axes[0, 0].legend(fontsize=8)
    fig.tight_layout()
    return png_of(fig)


def fig8_figure(accuracy):
    """Fig. 8: PNG of the e_RMS bars of ``motoflex study accuracy --plot``."""
    return png_of(accuracy_bars_figure(accuracy))


def fig10_figure(sensitivity):
    """Fig. 10: PNG of the Pearson bars of ``motoflex study sensitivity --plot``."""
    return png_of(pearson_bars_figure(sensitivity["pearson"]))
