"""Browser test: report.html of the example run, rendered in headless chromium (issue 16).

The report of a copy of bags/example is opened from file:// by Playwright
(test/headless_chromium.py). Each figure is screenshotted where the browser laid it out: its
plot region must not be blank (pixel statistics: ink on at least MIN_INK of its pixels, and data
drawn in colour on at least MIN_COLOURED: axes, ticks and text alone are black and grey) and it
must be shown at its own pixel width (not shrunk); the rendered text of
the stability section names the identified motorcycle; the first section the browser lays out
is the summary with the run's status (issue 24). MOTOFLEX_SAVE_REPORT_PNG=folder keeps
the screenshots.
"""
import io
import json
import os
from pathlib import Path

import numpy as np
import pytest
from example_runs import example_reported
from headless_chromium import HeadlessChromium, ensure_chromium
from PIL import Image

MIN_INK = 0.01
"""Least share of a figure's pixels that are not page white (a blank plot region has 0)."""
MIN_COLOURED = 0.002
"""Least share of a figure's pixels in colour (saturation above 60 of 255): the data drawn;
the example's figures have 0.5 % (a few curves) to 33 % (the bars of Fig. 8)."""
FIGURES = ("modes_frame", "modes_front_assembly", "modes_swingarm", "fig5_frame",
           "fig6_front_assembly", "fig7_swingarm", "fig8", "fig9", "fig10", "eig_touring")

LAYOUT_JS = """JSON.stringify(Array.from(document.querySelectorAll('figure img')).map(img => {
  const r = img.getBoundingClientRect();
  return {id: img.parentElement.id, x: r.left + window.scrollX, y: r.top + window.scrollY,
          width: r.width, height: r.height, natural: img.naturalWidth,
          complete: img.complete};
}))"""


def ink(png):
    """(share of pixels farther than 24 per channel from white, share of coloured pixels) of
    a PNG."""
    rgb = np.asarray(Image.open(io.BytesIO(png)).convert("RGB"), dtype=int)
    inked = (255 - rgb).max(axis=2) > 24
    coloured = (rgb.max(axis=2) - rgb.min(axis=2)) > 60
    return float(inked.mean()), float(coloured.mean())


@pytest.fixture(scope="module")
def report():
    return example_reported()


@pytest.mark.slow
def test_report_renders_plots_and_names_the_motorcycle_in_chromium(report):
    ensure_chromium()
    browser = HeadlessChromium()
    try:
        url = (report / "report.html").as_uri()
        browser.open(url)
        browser.wait_loaded(url)
        layout = {f["id"]: f for f in json.loads(browser.evaluate(LAYOUT_JS))}
        shots = {name: browser.screenshot({k: layout[name][k] for k in
                                           ("x", "y", "width", "height")})
                 for name in FIGURES if name in layout}
        stability = browser.evaluate("document.getElementById('section-vehicle').innerText")
        first = browser.evaluate("(() => { const s = document.querySelector('section'); "
                                 "return [s.id, s.innerText]; })()")
    finally:
        browser.close()
    keep = os.environ.get("MOTOFLEX_SAVE_REPORT_PNG")
    for name in FIGURES:
        box = layout[name]
        assert box["complete"] and box["natural"] > 0, name
        assert box["width"] >= box["natural"] - 0.5, f"{name} shrunk: {box}"
        share, coloured = ink(shots[name])
        if keep:
            Path(keep).mkdir(parents=True, exist_ok=True)
            (Path(keep) / f"{name}.png").write_bytes(shots[name])
        assert share >= MIN_INK and coloured >= MIN_COLOURED, (name, share, coloured)
    eig = json.loads((report / "eig.json").read_text())
    assert f"lumped '{eig['variant']}' variant" in stability
    assert "Vehicle stability" in stability
    # what a reader meets first: the summary, naming how the run ended and the verdict
    status = json.loads((report / "status.json").read_text())["status"]
    assert first[0] == "section-summary", first[0]
    assert f"Run {report.name}: {status}" in first[1] and "Verdict:" in first[1]


def _png(draw):
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6, 4))
    ax.set_xlabel("speed [km/h]")
    ax.set_ylabel("real part [1/s]")
    draw(ax)
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", dpi=100)
    plt.close(fig)
    return buffer.getvalue()


def test_ink_tells_a_blank_plot_region_from_a_plot():
    blank = io.BytesIO()
    Image.new("RGB", (300, 200), (255, 255, 255)).save(blank, format="PNG")
    assert ink(blank.getvalue()) == (0.0, 0.0)
    empty_axes = ink(_png(lambda ax: None))         # frame, ticks and labels, no data
    assert empty_axes[0] >= MIN_INK and empty_axes[1] < MIN_COLOURED
    one_curve = ink(_png(lambda ax: ax.plot([40, 210], [-5, -0.3], color="tab:blue")))
    assert one_curve[0] >= MIN_INK and one_curve[1] >= MIN_COLOURED
