"""PNG of a clamped component: undeformed structure, first torsion and first bending mode,
each seen in the x-z plane and in 3D (deformation exaggerated)."""
from dataclasses import dataclass

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from motoflex_ros.files import atomic_save_figure  # noqa: E402

__all__ = ["plot_component", "write_png_atomic", "mode_drawing", "ModeDrawing", "MODE_FRACTION"]

MODE_FRACTION = 0.12
"""Largest node translation of a drawn mode shape, as a fraction of the component's size."""


def write_png_atomic(fig, path):
    """Save ``fig`` as PNG atomically (nothing half-written)."""
    atomic_save_figure(fig, path, dpi=110)


@dataclass(frozen=True)
class ModeDrawing:
    """A mode drawn on a component: displaced node positions ``xyz`` [m] (n, 3), the mode's
    frequency [Hz], the ``scale`` [m sqrt(kg)] that multiplies the mass-normalised mode shape
    [1/sqrt(kg)] and the largest node translation drawn ``peak_m`` [m]."""

    label: str
    xyz: np.ndarray
    freq_hz: float
    scale: float
    peak_m: float

    def legend(self):
        """'first torsion 74.6 Hz, shape x 1.2e+00 (peak 0.08 m)': what is drawn, at which
        scale."""
        return (f"first {self.label} {self.freq_hz:.1f} Hz, shape x {self.scale:.2g} "
                f"(peak {self.peak_m:.2g} m)")


def mode_drawing(component, reduced, label, fraction=MODE_FRACTION):
    """The first mode of this label drawn with its largest node translation ``fraction`` of
    the component's size (None if the component has no such mode)."""
    i = reduced.first_mode(label)
    if i is None:
        return None
    disp = reduced.node_displacements(reduced.mode_shapes[:, i])[:, :3]
    peak_m = fraction * np.ptp(component.node_xyz, axis=0).max()
    scale = peak_m / max(np.abs(disp).max(), 1e-300)
    return ModeDrawing(label, component.node_xyz + scale * disp,
                       float(reduced.frequencies_hz[i]), float(scale), float(peak_m))


def _draw(ax, component, xyz, three_d, color):
    for n1, n2 in component.elements:
        pts = xyz[[n1, n2]]
        if three_d:
            ax.plot(pts[:, 0], pts[:, 1], pts[:, 2], color=color, lw=1.2)
        else:
            ax.plot(pts[:, 0], pts[:, 2], color=color, lw=1.2)
    clamps, end = component.clamp_xyz, component.q0
    if three_d:
        ax.scatter(clamps[:, 0], clamps[:, 1], clamps[:, 2], color="tab:blue", s=18)
        ax.scatter(*end, color="tab:orange", s=30)
    else:
        ax.scatter(clamps[:, 0], clamps[:, 2], color="tab:blue", s=18, zorder=3)
        ax.scatter(end[0], end[2], color="tab:orange", s=30, zorder=3)


def plot_component(component, reduced, path):
    """Write ``path`` (PNG): columns undeformed / torsion / bending; rows x-z / 3D."""
    fig = plt.figure(figsize=(13, 8))
    panels = [("undeformed", component.node_xyz, None)]
    for label in ("torsion", "bending"):
        mode = mode_drawing(component, reduced, label)
        panels.append((label, None, None) if mode is None else (label, mode.xyz, mode))
    for col, (label, xyz, mode) in enumerate(panels):
        title = label if mode is None else mode.legend()
        for row, three_d in enumerate((False, True)):
            ax = fig.add_subplot(2, 3, 1 + col + 3 * row,
                                 projection="3d" if three_d else None)
            if xyz is None:
                ax.set_title(f"no {label} mode")
                continue
            if label != "undeformed":
                _draw(ax, component, component.node_xyz, three_d, "0.8")
            _draw(ax, component, xyz, three_d, "k" if label == "undeformed" else "tab:red")
            ax.set_title(title + (" (3D)" if three_d else " (x-z)"), fontsize=9)
            ax.set_xlabel("x [m]")
            if three_d:
                ax.set_ylabel("y [m]")
                ax.set_zlabel("z [m]")
            else:
                ax.set_ylabel("z [m]")
                ax.set_aspect("equal", adjustable="datalim")
    fig.suptitle(f"{component.name}: clamped (blue), loaded end q0 (orange)")
    fig.tight_layout()
    write_png_atomic(fig, path)
    plt.close(fig)
