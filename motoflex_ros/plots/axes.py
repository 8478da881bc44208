"""Figs. 5-7 of the paper: a component in the x-z plane with its deformation axes.

One figure code for ``motoflex identify --plot`` and the report (:func:`axes_figure`). The
structure (grey), the clamp points (light blue) and the loaded end q0 (orange); the static
deformation axis (blue, solid), the torsion axis (green, solid) and the bending axis (red,
dashed) from the harmonic tests at the first torsion and bending eigenfrequencies, and the axes
of the frequency sweep (thin, shaded from light at its first to dark at its last frequency, on
the colour bar); beyond the paper, the principal hinges (purple dotted, brown dash-dotted:
:mod:`motoflex_ros.identify.principal`). Each axis passes through its joint at distance l from O
along O-q0 and makes the angle beta with O-q0 (eqs. 5-6); the legend gives l [m] and beta [deg]
of each (the JSON holds beta in rad).
"""
from types import SimpleNamespace

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from motoflex_ros.plots.component_figure import write_png_atomic  # noqa: E402

__all__ = ["axes_figure", "plot_component_axes", "plot_measured_axes", "axis_segment_xz",
           "drawn_axes",
           "AXIS_STYLES", "SWEEP_CMAP"]

AXIS_STYLES = {"static": {"color": "#1f77b4", "ls": "-", "lw": 2.5},
               "torsion": {"color": "#2ca02c", "ls": "-", "lw": 2.0},
               "bending": {"color": "#d62728", "ls": "--", "lw": 2.0},
               "principal 1": {"color": "#9467bd", "ls": ":", "lw": 2.5},
               "principal 2": {"color": "#8c564b", "ls": "-.", "lw": 2.0},
               "principal 3": {"color": "#e377c2", "ls": ":", "lw": 1.5}}
"""Colour and line style of each identified axis: no two alike (issue 16, point 7)."""
SWEEP_CMAP = "Greys"


def axis_segment_xz(l, beta, q0, half_length):
    """Two points (x, z) [m] of the axis (l, beta) of a component with loaded end q0."""
    theta0 = np.arctan2(q0[2], q0[0])
    joint = l * np.array([np.cos(theta0), np.sin(theta0)])
    direction = np.array([np.cos(theta0 + beta), np.sin(theta0 + beta)])
    return np.array([joint - half_length * direction, joint + half_length * direction])


def _structure(ax, component):
    xyz = component.node_xyz
    for k, (i, j) in enumerate(component.elements):
        ax.plot(xyz[[i, j], 0], xyz[[i, j], 2], color="0.6", lw=2, zorder=1,
                label="structure" if k == 0 else None)
    clamps = component.clamp_xyz
    ax.plot(clamps[:, 0], clamps[:, 2], "o", color="#5bc0eb", ms=9, zorder=4, label="clamp")


def _geometry(m):
    return f"l = {m['l']:.3f} m, \u03b2 = {np.degrees(m['beta']):.1f}\u00b0"


def _sweep(fig, ax, sweep, q0, half):
    """The sweep's axes shaded by test frequency, with a colour bar [Hz]."""
    if not sweep:
        return
    freqs = np.array([s["f_hz"] for s in sweep], float)
    norm = matplotlib.colors.Normalize(freqs.min() - 0.3 * np.ptp(freqs) - 1e-9, freqs.max())
    cmap = plt.get_cmap(SWEEP_CMAP)
    for i, point in enumerate(sweep):
        seg = axis_segment_xz(point["l"], point["beta"], q0, half)
        ax.plot(seg[:, 0], seg[:, 1], color=cmap(norm(freqs[i])), lw=0.8, zorder=2,
                label=(f"sweep axes: {len(sweep)} harmonic tests, {freqs.min():.0f}-"
                       f"{freqs.max():.0f} Hz") if i == len(sweep) - 1 else None)
    bar = fig.colorbar(matplotlib.cm.ScalarMappable(norm=norm, cmap=cmap), ax=ax,
                       shrink=0.8, pad=0.02)
    bar.set_label("sweep test frequency [Hz]")
    bar.ax.set_ylim(freqs.min(), freqs.max())


def drawn_axes(identified):
    """{name: model} of the axes a figure draws: static, torsion, bending (those present) and
    the principal hinges ('principal 1', ... when identified)."""
    out = {name: identified[name] for name in ("static", "torsion", "bending")
           if identified.get(name) is not None}
    principal = identified.get("principal") or {}
    if principal.get("identified"):
        out.update({f"principal {i + 1}": h for i, h in enumerate(principal["hinges"])})
    return out


def _axes(fig, ax, identified, q0, half):
    _sweep(fig, ax, identified.get("sweep", []), q0, half)
    drawn = drawn_axes(identified)
    for name in ("torsion", "bending", "static", *[n for n in drawn if n.startswith("princ")]):
        m = drawn.get(name)
        if m is None:   # a measured record without that test
            continue
        seg = axis_segment_xz(m["l"], m["beta"], q0, half)
        at = f" at {m['f_hz']:.1f} Hz" if "f_hz" in m else ""
        k = f", k = {m['k']:.3g} N m/rad" if name.startswith("principal") else ""
        ax.plot(seg[:, 0], seg[:, 1], zorder=3,
                label=f"{name} axis{at}: {_geometry(m)}{k}", **AXIS_STYLES[name])


def _limits(xyz, identified, q0):
    """(lower, upper) corners [m] of the view: structure, joints near it and the axes' feet."""
    length = float(np.linalg.norm(q0))
    points = [xyz[:, [0, 2]]]
    for m in drawn_axes(identified).values():
        behind, ahead = axis_segment_xz(m["l"], m["beta"], q0, 1.0)
        joint, direction = (behind + ahead) / 2.0, (ahead - behind) / 2.0
        foot = joint + np.dot(q0[[0, 2]] - joint, direction) * direction
        points.append(foot[None, :])  # the axis' point nearest to q0, |b| away from it
        if abs(m["l"]) < 2 * length:
            points.append(joint[None, :])
    points = np.vstack(points)
    return points.min(axis=0), points.max(axis=0)


def axes_figure(component, identified):
    """The figure of one component's deformation axes (Figs. 5-7).

    ``component``: the structures Component (node_xyz, elements, clamp_xyz, q0 [m], name);
    ``identified``: its identification in the JSON shape of ``motoflex identify`` (static,
    torsion, bending with l [m], beta [rad], f_hz [Hz]; sweep). Returns a matplotlib Figure.
    """
    q0 = np.asarray(component.q0, float)
    fig, ax = plt.subplots(figsize=(8.0, 6.5), layout="constrained")
    _structure(ax, component)
    lo, hi = _limits(component.node_xyz, identified, q0)
    span = max(hi[0] - lo[0], hi[1] - lo[1])
    _axes(fig, ax, identified, q0, 3.0 * max(span, float(np.linalg.norm(q0))))
    ax.plot(q0[0], q0[2], "o", color="#ff7f0e", ms=9, zorder=5, label="load point q0")
    ax.set_xlim(lo[0] - 0.15 * span, hi[0] + 0.15 * span)
    ax.set_ylim(lo[1] - 0.15 * span, hi[1] + 0.15 * span)
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("z [m]")
    ax.set_title(f"{component.name}: deformation axes in the x-z plane")
    fig.legend(loc="outside lower center", ncols=2, fontsize=8)
    ax.grid(alpha=0.3)
    return fig


def plot_component_axes(component, identified, path):
    """Write the PNG of :func:`axes_figure` to ``path``; returns ``path``."""
    fig = axes_figure(component, identified)
    try:
        write_png_atomic(fig, path)
    finally:
        plt.close(fig)
    return path


def plot_measured_axes(name, q0, identified, path):
    """The axes plot of an identification of measurements (no structure to draw: the line
    from the clamp at O to the loaded end q0 [m])."""
    q0 = np.asarray(q0, float)
    bench = SimpleNamespace(name=name, q0=q0, node_xyz=np.array([np.zeros(3), q0]),
                            elements=[(0, 1)], clamp_xyz=np.zeros((1, 3)))
    return plot_component_axes(bench, identified, path)
