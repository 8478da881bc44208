"""Figs. 5-7 of the paper: a component in the x-z plane with its deformation axes.

The structure (grey), the clamp points (light blue) and the loaded end q0 (orange); the static
deformation axis (blue), the torsion and bending axes from the harmonic tests at the first
torsion and bending eigenfrequencies (green), and the sweep axes from 1 Hz to 5 Hz below the
first eigenfrequency (thin black). Each axis passes through its joint at distance l from O
along O-q0 and makes the angle beta with O-q0 (eqs. 5-6).
"""
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from motoflex_ros.plots.components import write_png_atomic  # noqa: E402

__all__ = ["plot_component_axes", "plot_measured_axes", "axis_segment"]


def axis_segment(l, beta, q0, half_length):
    """Two points (x, z) [m] of the axis (l, beta) of a component with loaded end q0."""
    theta0 = np.arctan2(q0[2], q0[0])
    joint = l * np.array([np.cos(theta0), np.sin(theta0)])
    direction = np.array([np.cos(theta0 + beta), np.sin(theta0 + beta)])
    return np.array([joint - half_length * direction, joint + half_length * direction])



def _structure(ax, component):
    xyz = component.node_xyz
    for i, j in component.elements:
        ax.plot(xyz[[i, j], 0], xyz[[i, j], 2], color="0.6", lw=2, zorder=1)
    clamps = component.clamp_xyz
    ax.plot(clamps[:, 0], clamps[:, 2], "o", color="#5bc0eb", ms=9, zorder=4, label="clamp")


def _axes(ax, identification, q0, half):
    for i, point in enumerate(identification.sweep):
        seg = axis_segment(point["l"], point["beta"], q0, half)
        ax.plot(seg[:, 0], seg[:, 1], color="k", lw=0.6, alpha=0.7,
                label="sweep" if i == 0 else None, zorder=2)
    for name, style in (("torsion", "-"), ("bending", "--")):
        m = getattr(identification, name)
        if m is None:   # a measured record without that test
            continue
        seg = axis_segment(m["l"], m["beta"], q0, half)
        ax.plot(seg[:, 0], seg[:, 1], style, color="#2ca02c", lw=2,
                label=f"{name} ({m['f_hz']:.0f} Hz)", zorder=3)
    s = identification.static
    seg = axis_segment(s["l"], s["beta"], q0, half)
    ax.plot(seg[:, 0], seg[:, 1], color="#1f77b4", lw=2.5, label="static", zorder=3)


def plot_component_axes(setup, identification, path):
    """Write the PNG of one component's deformation axes (Figs. 5-7) to ``path``."""
    q0 = np.asarray(setup.reduced.q0, float)
    fig, ax = plt.subplots(figsize=(7.5, 6.0))
    if setup.component is not None:
        _structure(ax, setup.component)
        xyz = setup.component.node_xyz
    else:
        xyz = np.array([np.zeros(3), q0])
    length = float(np.linalg.norm(q0))
    points = [xyz[:, [0, 2]]]
    for m in (identification.static, identification.torsion, identification.bending):
        if m is None:
            continue
        behind, ahead = axis_segment(m["l"], m["beta"], q0, 1.0)
        joint, direction = (behind + ahead) / 2.0, (ahead - behind) / 2.0
        foot = joint + np.dot(q0[[0, 2]] - joint, direction) * direction
        points.append(foot[None, :])  # the axis' point nearest to q0, |b| away from it
        if abs(m["l"]) < 2 * length:
            points.append(joint[None, :])
    points = np.vstack(points)
    lo, hi = points.min(axis=0), points.max(axis=0)
    half = 3.0 * max(hi[0] - lo[0], hi[1] - lo[1], length)
    _axes(ax, identification, q0, half)
    ax.plot(q0[0], q0[2], "o", color="#ff7f0e", ms=9, zorder=5, label="load point q0")
    margin = 0.15 * max(hi[0] - lo[0], hi[1] - lo[1])
    ax.set_xlim(lo[0] - margin, hi[0] + margin)
    ax.set_ylim(lo[1] - margin, hi[1] + margin)
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("z [m]")
    ax.set_title(f"{setup.name}: deformation axes (static, torsion, bending, sweep)")
    ax.legend(loc="best", fontsize=8)
    ax.grid(alpha=0.3)
    write_png_atomic(fig, path)
    plt.close(fig)
    return path


def plot_measured_axes(name, q0, identification, path):
    """The axes plot of an identification of measurements (no structure to draw: the clamp
    at O and the loaded end q0 [m] only)."""
    from types import SimpleNamespace
    bench = SimpleNamespace(name=name, reduced=SimpleNamespace(q0=q0), component=None)
    return plot_component_axes(bench, identification, path)
