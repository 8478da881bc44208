"""Test helper: Debian's headless chromium (/usr/bin/chromium) driven by Playwright.

Playwright downloads its own browser builds from a CDN, which this project's machines cannot
reach (only package registries); it drives the system chromium through ``executable_path``
instead (checked with Playwright 1.65 and Chromium 156). Used by the browser tests of the rerun
web viewer (test_view_browser.py, test_rerun_browser.py) and of report.html
(test_report_browser.py). Chromium is installed by tools/install_chromium.sh when missing (CI
runs as root on a fresh machine; the script needs apt-get).
"""
import base64
import json
import os
import shutil
import subprocess
import time
from pathlib import Path

import pytest
from playwright.sync_api import sync_playwright

__all__ = ["CHROMIUM", "WINDOW", "FLAGS", "ensure_chromium", "HeadlessChromium"]

CHROMIUM = Path("/usr/bin/chromium")
ROOT = Path(__file__).resolve().parents[1]
WINDOW = (1280, 800)
FLAGS = ["--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync"]


def ensure_chromium():
    if CHROMIUM.exists():
        return
    if shutil.which("apt-get") is None:
        pytest.skip("chromium is not installed and apt-get is not available to install it")
    if os.geteuid() != 0:
        pytest.skip("chromium is not installed and installing it with apt-get needs root")
    result = subprocess.run(["bash", str(ROOT / "tools" / "install_chromium.sh")],
                            capture_output=True, text=True, timeout=600)
    assert result.returncode == 0, result.stderr[-2000:]


class HeadlessChromium:
    """One headless chromium with one page of ``window`` size (CSS px, default WINDOW).

    Chromium rasterizes in software here (swiftshader): its CPU per drawn frame grows with the
    window's pixels (measured on the rerun web viewer's redrawing views: 800x500 took 30-50 %
    less chromium CPU than 1280x800).
    """

    def __init__(self, extra_flags=(), window=WINDOW):
        self._playwright = sync_playwright().start()
        try:
            self._browser = self._playwright.chromium.launch(
                executable_path=str(CHROMIUM), headless=True, args=[*FLAGS, *extra_flags])
            self._page = self._browser.new_page(
                viewport={"width": window[0], "height": window[1]})
            self._cdp = self._page.context.new_cdp_session(self._page)
        except Exception:
            self._playwright.stop()
            raise

    def open(self, url):
        """Navigate to ``url`` without waiting for it to load (:meth:`wait_loaded` waits)."""
        self._page.goto(url, wait_until="commit")

    def screenshot(self, clip=None, beyond_viewport=True):
        """PNG of the viewport, or of ``clip`` {x, y, width, height} [CSS px] of the page
        (``beyond_viewport``: anywhere on the page; else inside the viewport, which is not
        resized for the capture: a canvas is not drawn again).

        Taken with the DevTools call itself (Page.captureScreenshot through Playwright's CDP
        session): Playwright's own page.screenshot waits for the page to settle and timed out
        (30 s) on the rerun web viewer, whose WebGL canvas redraws without end.
        """
        params = {"format": "png"}
        if clip is not None:
            params.update(clip={**clip, "scale": 1}, captureBeyondViewport=beyond_viewport)
        return base64.b64decode(self._cdp.send("Page.captureScreenshot", params)["data"])

    def evaluate(self, expression):
        """The value of a JavaScript expression in the open page (returned by value)."""
        return self._page.evaluate(expression)

    def wait_loaded(self, url, limit_s=60.0):
        """Wait until the open page is ``url`` and its document (with its images) has loaded."""
        deadline = time.monotonic() + limit_s
        check = f"location.href === {json.dumps(url)} && document.readyState === 'complete'"
        while not self.evaluate(check):
            assert time.monotonic() < deadline, "the page did not load"
            time.sleep(0.2)

    def close(self):
        try:
            self._browser.close()
        finally:
            self._playwright.stop()
