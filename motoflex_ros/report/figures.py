"""Figures of the report as PNG bytes (matplotlib, Agg): components with their modes, the
deformation axes of Figs. 5-7, the front-assembly curves of Fig. 9, and Figs. 8 and 10 through
:mod:`motoflex_ros.plots.study`. Imported lazily by ``motoflex report``.
"""
import functools
import io
import tempfile
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from motoflex_ros.report.geometry import axis_segment  # noqa: E402
from motoflex_ros.units import ms_to_kmh  # noqa: E402

__all__ = ["png_of", "component_modes_figure", "axes_figure", "fig9_figure", "fig8_figure",
           "fig10_figure", "component_model"]

CLAMP = "#5ac8ff"
LOAD = "#ff8c00"
MODE_COLORS = {"torsion": "#1eaa3c", "bending": "#2a6eff"}


def png_of(fig):
    """PNG bytes of a matplotlib figure (closed afterwards)."""
    buffer = io.BytesIO()
    try:
        fig.savefig(buffer, format="png", dpi=100)
    finally:
        plt.close(fig)
    return buffer.getvalue()


@functools.cache
def component_model(name):
    """(Component, ReducedComponent) of a shipped component (built once per process)."""
    from motoflex_ros.structures import load_component
    component = load_component(name)
    return component, component.clamped_reduced()


def _draw_beams(ax, xyz, elements, dims, **style):
    for i, j in elements:
        ax.plot(xyz[[i, j], dims[0]], xyz[[i, j], dims[1]], **style)


def _mode_translations(reduced, index, size):
    shape = reduced.node_displacements(reduced.mode_shapes[:, index])[:, :3]
    peak = np.abs(shape).max()
    return shape * (0.1 * size / peak if peak > 0 else 0.0)


def component_modes_figure(name):
    """Side (x-z) and top (x-y) views of a component with its first torsion and bending modes.

    Mode shapes are the clamped reduced model's, scaled so the largest node translation is a
    tenth of the component's size.
    """
    component, reduced = component_model(name)
    xyz, elements = component.node_xyz, component.elements
    size = np.ptp(xyz, axis=0).max()
    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    for ax, dims, title in zip(axes, ((0, 2), (0, 1)), ("side (x-z)", "top (x-y)")):
        _draw_beams(ax, xyz, elements, dims, color="0.6", lw=1.5)
        for label, color in MODE_COLORS.items():
            index = reduced.first_mode(label)
            if index is None:
                continue
            moved = xyz + _mode_translations(reduced, index, size)
            _draw_beams(ax, moved, elements, dims, color=color, lw=1.0)
            ax.plot([], [], color=color,
                    label=f"first {label}: {reduced.frequencies_hz[index]:.1f} Hz")
        ax.plot(*component.clamp_xyz[:, dims].T, "o", color=CLAMP)
        ax.plot(*component.q0[list(dims)], "o", color=LOAD)
        ax.set_aspect("equal")
        ax.set_title(f"{name}: {title}")
        ax.set_xlabel("x [m]")
        ax.set_ylabel("z [m]" if dims[1] == 2 else "y [m]")
    axes[0].legend(fontsize=8)
    fig.tight_layout()
    return png_of(fig)


def axes_figure(name, identified):
    """Figs. 5-7: deformation axes in the x-z plane (static blue, torsion and bending green,
    sweep thin black), clamp points light blue, load point orange."""
    component, _ = component_model(name)
    q0 = component.q0
    fig, ax = plt.subplots(figsize=(6, 4.5))
    _draw_beams(ax, component.node_xyz, component.elements, (0, 2), color="0.7", lw=1.2)
    for step in identified.get("sweep", []):
        seg = axis_segment(step["l"], step["beta"], q0)
        ax.plot(seg[:, 0], seg[:, 2], color="black", lw=0.5)
    for test, color in (("torsion", "#1eaa3c"), ("bending", "#1eaa3c"), ("static", "#2a6eff")):
        seg = axis_segment(identified[test]["l"], identified[test]["beta"], q0)
        ax.plot(seg[:, 0], seg[:, 2], color=color, lw=2, label=test)
        ax.annotate(test, seg[1, [0, 2]], fontsize=8, color=color)
    ax.plot(component.clamp_xyz[:, 0], component.clamp_xyz[:, 2], "o", color=CLAMP,
            label="clamp")
    ax.plot(q0[0], q0[2], "o", color=LOAD, label="load")
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("z [m]")
    ax.set_title(f"{name}: deformation axes")
    ax.legend(fontsize=8, loc="best")
    fig.tight_layout()
    return png_of(fig)


def _mode_curve(eig, mode):
    speeds = ms_to_kmh(eig["speeds_mps"])
    pairs = [(np.nan, np.nan) if z is None else z for z in eig["modes"][mode]]
    values = np.array(pairs, float)
    return speeds, values[:, 0], values[:, 1] / (2 * np.pi)


def fig9_figure(variants):
    """Fig. 9: weave and wobble frequency and real part against speed, front assembly flexible
    only, per model variant (``variants``: {variant: eig JSON})."""
    fig, axes = plt.subplots(2, 2, figsize=(10, 7), sharex=True)
    for col, mode in enumerate(("weave", "wobble")):
        for variant, eig in variants.items():
            speeds, real, freq = _mode_curve(eig, mode)
            style = {"lw": 2.5, "color": "black"} if variant == "flexible" else {"lw": 1.2}
            axes[0, col].plot(speeds, freq, label=variant, **style)
            axes[1, col].plot(speeds, real, label=variant, **style)
        axes[0, col].set_title(mode)
        axes[0, col].set_ylabel("frequency [Hz]")
        axes[1, col].set_ylabel("real part [1/s]")
        axes[1, col].set_xlabel("speed [km/h]")
    axes[0, 0].legend(fontsize=8)
    fig.tight_layout()
    return png_of(fig)


def _via_file(plot, data):
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "figure.png"
        plot(data, path)
        return path.read_bytes()


def fig8_figure(accuracy):
    """Fig. 8: e_RMS bars (plots.study.plot_accuracy_bars)."""
    from motoflex_ros.plots.study import plot_accuracy_bars
    return _via_file(plot_accuracy_bars, accuracy)


def fig10_figure(sensitivity):
    """Fig. 10: Pearson bars (plots.study.plot_pearson_bars)."""
    from motoflex_ros.plots.study import plot_pearson_bars
    return _via_file(plot_pearson_bars, sensitivity["pearson"])
