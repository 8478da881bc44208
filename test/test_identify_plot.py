"""Figs. 5-7 plot: the axes drawn are the identified ones (segment geometry round trip)."""
import numpy as np
import pytest

from motoflex_ros.bench.offline_campaign import run_campaign, setup_campaign, with_sensor
from motoflex_ros.formats.component_file import load_component
from motoflex_ros.identify.peaks import unwrap_angle
from motoflex_ros.lumped_stiffness.axis import deformation_axis


def test_axis_segment_roundtrip():
    """A segment drawn for (l, beta) lies on the axis that eqs. (3)-(6) identify."""
    from motoflex_ros.plots.axes import axis_segment_xz
    q0 = np.array([-0.6, 0.0, -0.045])
    for l, beta in [(0.23, 1.54), (-2.9, 2.87), (0.4, 0.05)]:
        p, r = axis_segment_xz(l, beta, q0, 0.7)
        direction = (r - p) / np.linalg.norm(r - p)
        n = np.array([-direction[1], 0.0, direction[0]])  # normal of the axis in x-z
        tilt = 1e-6
        normal = np.array([tilt * n[0], 1.0, tilt * n[2]])
        rot = np.column_stack([np.cross(normal, [0, 0, 1]), normal, [0, 0, 1]])
        q = q0 + np.array([0.0, -tilt * np.dot(n, q0 - np.r_[p[0], 0.0, p[1]]), 0.0])
        axis = deformation_axis(q, rot, q0)
        assert axis.l == pytest.approx(l, abs=1e-6 * max(1.0, abs(l)))
        assert unwrap_angle(axis.beta, beta) == pytest.approx(beta, abs=1e-9)


def test_plot_component_axes_writes_png(tmp_path):
    from motoflex_ros.plots.axes import plot_component_axes
    setup = with_sensor(setup_campaign(load_component("swingarm")), noise_m=0.0, resolution_m=0.0)
    result = run_campaign(setup).identification.to_dict()
    path = plot_component_axes(setup.component, result, tmp_path / "swingarm_axes.png")
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_principal_axes_drawn_beside_the_papers():
    """Issue 22: the principal hinges' axes are drawn with the static, torsion and bending
    ones, each on its own (l, beta) line."""
    import matplotlib.pyplot as plt

    from motoflex_ros.bench.offline_campaign import identify_components
    from motoflex_ros.formats.component_file import load_components
    from motoflex_ros.plots.axes import axes_figure, axis_segment_xz, drawn_axes
    from motoflex_ros.study.identified_variants import carried_inertias
    components = load_components(["swingarm"])
    carried = carried_inertias(components)
    setup, run = identify_components(components, noise_m=0.0, carried=carried)["swingarm"]
    result = run.identification.to_dict()
    drawn = drawn_axes(result)
    assert list(drawn) == ["static", "torsion", "bending", "principal 1", "principal 2"]
    fig = axes_figure(setup.component, result)
    try:
        lines = {line.get_label().split(" axis")[0]: line for line in fig.axes[0].lines}
        for name in ("principal 1", "principal 2"):
            hinge = drawn[name]
            seg = axis_segment_xz(hinge["l"], hinge["beta"], setup.reduced.q0, 1.0)
            xs, zs = lines[name].get_data()
            direction = (seg[1] - seg[0]) / np.linalg.norm(seg[1] - seg[0])
            for x, z in zip(xs, zs):   # the drawn points lie on the hinge's line
                offset = np.array([x, z]) - seg[0]
                assert abs(offset[0] * direction[1] - offset[1] * direction[0]) < 1e-9
    finally:
        plt.close(fig)
