"""Browser test: `motoflex view RUN --web` in headless Debian chromium shows a non-empty 3D view.

The page is driven by Playwright (test/headless_chromium.py): screenshots are
taken until the bench's 3D view shows the orange beam model, or a time limit passes. Set
MOTOFLEX_SAVE_VIEWER_PNG=path to keep the screenshot (docs/viewer.png in the README).
"""
import io
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from headless_chromium import HeadlessChromium, ensure_chromium
from PIL import Image
from processes import processes_naming

from motoflex_ros.record.rerun_log import STRUCTURE_COLOR

LOAD_LIMIT_S = 90.0
STRUCTURE_RGB = np.array(STRUCTURE_COLOR)


def beam_pixels(png, box):
    """Pixels of the beam model's orange (within 60 per channel of (230, 130, 30)) in box.

    box = (left, top, right, bottom). Nothing else the viewer draws is this orange: panels,
    grid and text are grey, highlights blue; the orange 'Software rasterizer' note sits in the
    top bar, outside the box.
    """
    rgb = np.asarray(Image.open(io.BytesIO(png)).convert("RGB"), dtype=int)
    left, top, right, bottom = box
    area = rgb[top:bottom, left:right]
    return int((np.abs(area - STRUCTURE_RGB).max(axis=2) < 60).sum())


WINDOW = (800, 600)
"""The browser's window [CSS px], small: chromium rasterizes in software, its CPU grows with
the pixels (see test_rerun_browser.WINDOW). The beam model then covers about 1,000 pixels
of VIEW_BOX (2,827 at 1280x800)."""
# the bench 3D view: left three fifths of the window, below the top bar, above the time panel
VIEW_BOX = (0, 60, int(0.6 * WINDOW[0]), 440)
MIN_BEAM_PIXELS = 400


def _address(view):
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline:
        line = view.stdout.readline()
        if not line:
            break
        if "http://127.0.0.1:" in line:
            return line.split(": ", 1)[1].strip()
    pytest.fail(f"motoflex view printed no address: {view.stderr.read()[-2000:]}")


@pytest.fixture()
def served_run(tmp_path):
    from test_rerun_bag import make_bag
    bag = tmp_path / "run1"
    make_bag(bag)
    view = subprocess.Popen([sys.executable, "-m", "motoflex_ros.cli.main", "view", str(bag),
                             "--web"], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True)
    try:
        address = _address(view)
        # the rerun binary reads the recording from its stdin: its command line names no file
        viewer = Path(f"/proc/{view.pid}/task/{view.pid}/children").read_text().split()
        assert viewer
        yield address
    finally:
        view.terminate()
        view.wait(timeout=30)
    assert not processes_naming(bag)   # the viewer went with it
    assert not [pid for pid in viewer if Path(f"/proc/{pid}").exists()]


@pytest.mark.slow
def test_view_web_shows_3d_bench_in_chromium(served_run):
    ensure_chromium()
    assert served_run.startswith("http://127.0.0.1:")
    browser = HeadlessChromium(window=WINDOW)
    try:
        browser.open(served_run)
        deadline = time.monotonic() + LOAD_LIMIT_S
        count, png = 0, b""
        while time.monotonic() < deadline and count < MIN_BEAM_PIXELS:
            time.sleep(0.5)
            png = browser.screenshot()
            count = beam_pixels(png, VIEW_BOX)
    finally:
        browser.close()
    keep = os.environ.get("MOTOFLEX_SAVE_VIEWER_PNG")
    if keep and png:
        Path(keep).write_bytes(png)
    assert count >= MIN_BEAM_PIXELS, f"3D view shows only {count} pixels of the beam model"


def test_beam_pixels_counts_only_the_beam_colour():
    image = Image.new("RGB", (20, 10), (13, 17, 19))
    for x in range(5):
        image.putpixel((x, 2), STRUCTURE_COLOR)     # beam pixels
        image.putpixel((x, 4), (200, 200, 200))     # grey grid pixels
        image.putpixel((x, 6), (0, 110, 255))       # blue selection highlight
    buffer = io.BytesIO()
    image.save(buffer, format="PNG")
    assert beam_pixels(buffer.getvalue(), (0, 0, 20, 10)) == 5
    assert beam_pixels(buffer.getvalue(), (0, 3, 20, 10)) == 0
