"""Plots of a vehicle's modal sweep: root locus, and weave/wobble frequency and real part
against speed (the style of Fig. 9 of Passigato et al. 2023). PNG files, written atomically."""
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from motoflex_ros.files import atomic_save_figure  # noqa: E402
from motoflex_ros.units import ms_to_kmh  # noqa: E402
from motoflex_ros.vehicle.mode_names import STUDIED_MODES

__all__ = ["plot_modal_sweep", "save_png"]


def save_png(fig, path, dpi=120):
    """Write a figure as PNG atomically, close it; returns the path."""
    try:
        return atomic_save_figure(fig, path, dpi)
    finally:
        plt.close(fig)


def _root_locus(sweep, title):
    fig, ax = plt.subplots(figsize=(7, 5))
    kmh = np.concatenate([np.full(len(ev), ms_to_kmh(v)) for v, ev in zip(sweep.speeds,
                                                                      sweep.eigenvalues)])
    values = np.concatenate(sweep.eigenvalues)
    keep = (values.imag >= 0) & (np.abs(values) < 150.0)
    points = ax.scatter(values.real[keep], values.imag[keep] / (2 * np.pi), c=kmh[keep], s=8,
                        cmap="viridis")
    for name, marker in (("weave", "o"), ("wobble", "s"), ("capsize", "^")):
        z = sweep.modes[name]
        ax.plot(z.real, z.imag / (2 * np.pi), marker, mfc="none", color="k", ms=5, label=name)
    ax.axvline(0.0, color="grey", lw=0.8)
    ax.set_xlabel("real part [1/s]")
    ax.set_ylabel("frequency [Hz]")
    ax.set_title(f"{title}: root locus")
    ax.legend()
    fig.colorbar(points, ax=ax, label="speed [km/h]")
    fig.tight_layout()
    return fig


def _modes_over_speed(sweep, title):
    fig, axes = plt.subplots(2, 2, figsize=(9, 6), sharex=True)
    kmh = ms_to_kmh(sweep.speeds)
    for col, name in enumerate(STUDIED_MODES):
        axes[0, col].plot(kmh, sweep.frequency_hz(name), "o-", ms=3)
        axes[0, col].set_ylabel(f"{name} frequency [Hz]")
        axes[1, col].plot(kmh, sweep.real_part(name), "o-", ms=3)
        axes[1, col].axhline(0.0, color="grey", lw=0.8)
        axes[1, col].set_ylabel(f"{name} real part [1/s]")
        axes[1, col].set_xlabel("speed [km/h]")
    fig.suptitle(f"{title}: weave and wobble")
    fig.tight_layout()
    return fig


def plot_modal_sweep(sweep, folder, title):
    """Write root_locus.png and weave_wobble.png into ``folder``; returns the paths."""
    folder = Path(folder)
    return [save_png(_root_locus(sweep, title), folder / "root_locus.png"),
            save_png(_modes_over_speed(sweep, title), folder / "weave_wobble.png")]
