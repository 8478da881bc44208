"""Browser test: `motoflex view RUN --web` in headless Debian chromium shows a non-empty 3D view.

Chromium is installed by tools/install_chromium.sh when missing (CI runs as root on a fresh
machine; the script needs apt-get). The page is driven over the DevTools protocol on a pipe
(--remote-debugging-pipe, stdlib only): screenshots are taken until the bench's 3D view shows
the orange beam model, or a time limit passes. Set
MOTOFLEX_SAVE_VIEWER_PNG=path to keep the screenshot (docs/viewer.png in the README).
"""
import base64
import fcntl
import io
import json
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from motoflex_ros.record.rerun_log import STRUCTURE_COLOR

CHROMIUM = Path("/usr/bin/chromium")
ROOT = Path(__file__).resolve().parents[1]
WINDOW = (1280, 800)
LOAD_LIMIT_S = 90.0
STRUCTURE_RGB = np.array(STRUCTURE_COLOR)
FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
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


class DevTools:
    """Minimal Chrome DevTools protocol client over --remote-debugging-pipe (fds 3 and 4)."""

    def __init__(self, extra_flags=()):
        def high(fd):
            moved = fcntl.fcntl(fd, fcntl.F_DUPFD_CLOEXEC, 10)
            os.close(fd)
            return moved
        to_chrome, self._out = map(high, os.pipe())
        self._in, from_chrome = map(high, os.pipe())
        self._profile = tempfile.mkdtemp(prefix="motoflex-chromium-")
        cmd = [str(CHROMIUM), *FLAGS, f"--user-data-dir={self._profile}",
               f"--window-size={WINDOW[0]},{WINDOW[1]}", "--remote-debugging-pipe",
               *extra_flags, "about:blank"]
        actions = [(os.POSIX_SPAWN_DUP2, to_chrome, 3), (os.POSIX_SPAWN_DUP2, from_chrome, 4),
                   (os.POSIX_SPAWN_OPEN, 1, os.devnull, os.O_WRONLY, 0),
                   (os.POSIX_SPAWN_OPEN, 2, os.devnull, os.O_WRONLY, 0)]
        self.pid = os.posix_spawn(cmd[0], cmd, os.environ, file_actions=actions, setpgroup=0)
        os.close(to_chrome)
        os.close(from_chrome)
        self._buffer = b""
        self._next_id = 0
        self.session = None

    def call(self, method, params=None, session=None):
        self._next_id += 1
        message = {"id": self._next_id, "method": method, "params": params or {}}
        if session:
            message["sessionId"] = session
        os.write(self._out, json.dumps(message).encode() + b"\0")
        while True:
            while b"\0" in self._buffer:
                raw, self._buffer = self._buffer.split(b"\0", 1)
                reply = json.loads(raw)
                if reply.get("id") == self._next_id:
                    assert "error" not in reply, reply
                    return reply["result"]
            chunk = os.read(self._in, 1 << 20)
            assert chunk, "chromium closed the DevTools pipe"
            self._buffer += chunk

    def open(self, url):
        target = self.call("Target.createTarget", {"url": url})["targetId"]
        self.session = self.call("Target.attachToTarget",
                                 {"targetId": target, "flatten": True})["sessionId"]

    def screenshot(self):
        data = self.call("Page.captureScreenshot", {"format": "png"}, self.session)["data"]
        return base64.b64decode(data)

    def close(self):
        os.killpg(self.pid, signal.SIGTERM)
        os.waitpid(self.pid, 0)
        os.close(self._in)
        os.close(self._out)
        shutil.rmtree(self._profile, ignore_errors=True)


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


# the bench 3D view: left three fifths of the window, below the top bar, above the time panel
VIEW_BOX = (0, 60, int(0.6 * WINDOW[0]), 500)
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
        yield _address(view)
    finally:
        view.terminate()
        view.wait(timeout=30)


@pytest.mark.slow
def test_view_web_shows_3d_bench_in_chromium(served_run):
    ensure_chromium()
    assert served_run.startswith("http://127.0.0.1:")
    browser = DevTools()
    try:
        browser.open(served_run)
        deadline = time.monotonic() + LOAD_LIMIT_S
        count, png = 0, b""
        while time.monotonic() < deadline and count < MIN_BEAM_PIXELS:
            time.sleep(2.0)
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
