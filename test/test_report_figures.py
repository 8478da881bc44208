"""The report's figures as drawn (issue 16, point 7), on the example run's identified values.

Checked on the matplotlib figures after drawing: the static, torsion and bending axes differ in
colour or line style (they were all solid green but one), no two texts overlap and none is cut
off at the figure's edge (the swingarm's 'bestatic' and its clipped z label), every Fig. 8 bar
is at least a few pixels tall (0.02 % beside 65 % on one linear axis was invisible), the
categories are named, and the mode shapes are drawn at the scale they state.
"""
import json
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
import pytest

from motoflex_ros.structures.paper_tables import COMPONENTS

EXAMPLE = Path(__file__).resolve().parents[1] / "bags" / "example"
MIN_BAR_PX = 3.0
MIN_LABEL_PX = 10.0


def _example(name):
    path = EXAMPLE / name
    if not path.is_file():
        pytest.skip("bags/example is not in this checkout")
    return json.loads(path.read_text())


def _tick_labels(axis):
    """The tick labels matplotlib draws: those of ticks inside the axis' view interval."""
    lo, hi = sorted(axis.get_view_interval())
    tolerance = 1e-9 * max(abs(lo), abs(hi), 1.0)
    return [label for tick in (*axis.get_major_ticks(), *axis.get_minor_ticks())
            if lo - tolerance <= tick.get_loc() <= hi + tolerance
            for label in (tick.label1, tick.label2) if label.get_visible()]


def _texts(fig):
    """(text, window extent) of every drawn, non-empty text of the figure."""
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    texts = [*fig.texts, *(t for legend in fig.legends for t in legend.get_texts())]
    if fig._suptitle is not None:
        texts.append(fig._suptitle)
    for ax in fig.axes:
        if not ax.get_visible():
            continue
        texts += [ax.title, ax._left_title, ax._right_title, ax.xaxis.label, ax.yaxis.label,
                  *ax.texts, *_tick_labels(ax.xaxis), *_tick_labels(ax.yaxis)]
        if ax.get_legend() is not None:
            texts += ax.get_legend().get_texts()
    unique = {id(t): t for t in texts}.values()
    return [(t.get_text(), t.get_window_extent(renderer)) for t in unique
            if t.get_visible() and t.get_text().strip()]


def assert_texts_readable(fig):
    """No text outside the figure, no two texts overlapping (by more than 1 px)."""
    width, height = fig.canvas.get_width_height()
    texts = _texts(fig)
    for text, box in texts:
        assert box.x0 >= -0.5 and box.y0 >= -0.5, f"{text!r} cut off: {box}"
        assert box.x1 <= width + 0.5 and box.y1 <= height + 0.5, f"{text!r} cut off: {box}"
    for i, (a, box_a) in enumerate(texts):
        for b, box_b in texts[i + 1:]:
            overlap_x = min(box_a.x1, box_b.x1) - max(box_a.x0, box_b.x0)
            overlap_y = min(box_a.y1, box_b.y1) - max(box_a.y0, box_b.y0)
            assert min(overlap_x, overlap_y) <= 1.0, f"{a!r} overlaps {b!r}"


@pytest.mark.parametrize("name", COMPONENTS)
def test_axes_figure_styles_differ_and_texts_are_readable(name):
    from motoflex_ros.plots.axes import axes_figure
    from motoflex_ros.report.figures import component_model
    fig = axes_figure(component_model(name)[0], _example("identification.json")[name])
    try:
        handles = {h.get_label().split(" axis")[0]: h for h in fig.legends[0].legend_handles}
        styles = {n: (handles[n].get_color(), handles[n].get_linestyle())
                  for n in ("static", "torsion", "bending")}
        assert len(set(styles.values())) == 3, styles
        assert len({c for c, _ in styles.values()}) == 3     # and three colours
        sweep = [h.get_label() for h in fig.legends[0].legend_handles
                 if h.get_label().startswith("sweep")]
        assert sweep and "harmonic tests" in sweep[0] and "Hz" in sweep[0]
        assert any("\u03b2 =" in h.get_label() and "\u00b0" in h.get_label()
                   for h in handles.values())
        assert_texts_readable(fig)
    finally:
        plt.close(fig)


@pytest.mark.parametrize("name", COMPONENTS)
def test_mode_figures_are_readable_and_scaled_as_stated(name):
    from motoflex_ros.plots.component_figure import MODE_FRACTION, mode_drawing
    from motoflex_ros.report.figures import component_model, modes_plot
    fig = modes_plot(name)
    try:
        assert_texts_readable(fig)
        legend = [t.get_text() for t in fig.legends[0].get_texts()]
    finally:
        plt.close(fig)
    component, reduced = component_model(name)
    size = np.ptp(component.node_xyz, axis=0).max()
    for label in ("torsion", "bending"):
        mode = mode_drawing(component, reduced, label)
        drawn = np.abs(mode.xyz - component.node_xyz).max()
        assert drawn == pytest.approx(MODE_FRACTION * size, rel=1e-12)
        shape = reduced.node_displacements(reduced.mode_shapes[:, reduced.first_mode(label)])
        assert drawn == pytest.approx(mode.scale * np.abs(shape[:, :3]).max(), rel=1e-12)
        assert any(f"shape x {mode.scale:.2g}" in t for t in legend)


def test_fig8_every_bar_visible_and_named():
    """Every bar of every variant in the JSON is drawn, long enough to see, named, with its
    value written beside it horizontally in a readable size."""
    from motoflex_ros.plots.study_figures import accuracy_bars_figure
    accuracy = _example("accuracy.json")
    smallest = min(v for case in accuracy.values() for variant in case.values()
                   for v in variant.values())
    assert smallest < 0.05      # the example has values of 0.02 %
    fig = accuracy_bars_figure(accuracy)
    try:
        fig.canvas.draw()
        bars = [p for ax in fig.axes for p in ax.patches]
        # one bar per case, variant and quantity (one panel per quantity)
        assert len(bars) == sum(len(variants) * len(next(iter(variants.values())))
                                for variants in accuracy.values())
        lengths = [p.get_window_extent().width for p in bars]     # horizontal bars
        assert min(lengths) >= MIN_BAR_PX, min(lengths)
        ticks = [t.get_text() for ax in fig.axes for t in ax.get_yticklabels()]
        assert ticks and all("_" not in t for t in ticks)
        # the values beside the bars: horizontal and at least MIN_LABEL_PX tall at the
        # report's resolution (they were 5 px and turned on end)
        from motoflex_ros.report.figures import DPI
        for ax in fig.axes:
            for text in ax.texts:
                assert text.get_rotation() == 0.0, text.get_text()
                assert text.get_fontsize() * DPI / 72.0 >= MIN_LABEL_PX, text.get_fontsize()
        legend = [t.get_text() for t in fig.legends[0].get_texts()]
        assert all("_" not in t for t in legend)
        values = {float(t.get_text()) for ax in fig.axes for t in ax.texts}
        assert float(f"{smallest:.2g}") in values       # the values are written on the bars
        assert_texts_readable(fig)
    finally:
        plt.close(fig)


def test_fig10_texts_readable():
    from motoflex_ros.plots.study_figures import pearson_bars_figure
    fig = pearson_bars_figure(_example("sensitivity.json")["pearson"])
    try:
        assert_texts_readable(fig)
    finally:
        plt.close(fig)


def test_readability_check_catches_overlap_and_clipping():
    """The check itself: two labels on one spot, and a label beyond the edge, are caught."""
    fig, ax = plt.subplots(figsize=(4, 3))
    ax.annotate("bending", (0.5, 0.5))
    ax.annotate("static", (0.5, 0.5))
    with pytest.raises(AssertionError, match="overlaps"):
        assert_texts_readable(fig)
    plt.close(fig)
    fig, ax = plt.subplots(figsize=(4, 3))
    fig.text(-0.05, 0.5, "z [m]")
    with pytest.raises(AssertionError, match="cut off"):
        assert_texts_readable(fig)
    plt.close(fig)
