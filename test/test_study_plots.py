"""Study plots: Fig. 10, Fig. 8 and Fig. 4 style PNG files are written whole."""
import matplotlib.image
import numpy as np

from motoflex_ros.plots.study_figures import (
    plot_accuracy_bars,
    plot_pearson_bars,
    plot_stability_curves,
)
from motoflex_ros.study.factorial import FACTORS


def _assert_png(path):
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    image = matplotlib.image.imread(path)
    assert image.shape[0] > 200 and image.shape[1] > 400
    assert not list(path.parent.glob(".*.tmp")) and not list(path.parent.glob(".*.png"))


def test_pearson_bars_png(tmp_path):
    pearson = {f"{m}_{r}": {f: np.sin(i + len(m) + len(r)) for i, f in enumerate(FACTORS)}
               for m in ("weave", "wobble") for r in ("low", "high")}
    _assert_png(plot_pearson_bars(pearson, tmp_path / "fig10.png"))


def test_accuracy_bars_png(tmp_path):
    quantities = ("weave_f", "weave_re", "wobble_f", "wobble_re")
    errors = {case: {variant: {q: 1.0 + i + j for j, q in enumerate(quantities)}
                     for i, variant in enumerate(("state_of_the_art", "static"))}
              for case in ("frame", "front_assembly", "swingarm", "all")}
    _assert_png(plot_accuracy_bars(errors, tmp_path / "sub" / "fig8.png"))


def test_stability_curves_png(tmp_path):
    speeds = np.linspace(40, 210, 171) / 3.6
    curves = np.stack([-0.5 + 0.01 * speeds, 0.3 - 0.02 * speeds])
    _assert_png(plot_stability_curves(speeds, curves, tmp_path / "fig4.png", labels=["a", "b"]))
