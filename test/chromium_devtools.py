"""Test helper: headless Debian chromium driven over the DevTools protocol on a pipe.

--remote-debugging-pipe (fds 3 and 4), stdlib only; used by the browser tests of the rerun web
viewer (test_view_browser.py) and of report.html (test_report_browser.py). Chromium is
installed by tools/install_chromium.sh when missing (CI runs as root on a fresh machine; the
script needs apt-get).
"""
import base64
import fcntl
import json
import os
import shutil
import signal
import subprocess
import tempfile
import time
from pathlib import Path

import pytest

__all__ = ["CHROMIUM", "WINDOW", "FLAGS", "ensure_chromium", "DevTools"]

CHROMIUM = Path("/usr/bin/chromium")
ROOT = Path(__file__).resolve().parents[1]
WINDOW = (1280, 800)
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

    def screenshot(self, clip=None):
        """PNG of the viewport, or of ``clip`` {x, y, width, height} [CSS px] of the page."""
        params = {"format": "png"}
        if clip is not None:
            params.update(clip={**clip, "scale": 1}, captureBeyondViewport=True)
        data = self.call("Page.captureScreenshot", params, self.session)["data"]
        return base64.b64decode(data)

    def evaluate(self, expression):
        """The value of a JavaScript expression in the open page (returned by value)."""
        reply = self.call("Runtime.evaluate", {"expression": expression, "returnByValue": True},
                          self.session)
        assert "exceptionDetails" not in reply, reply
        return reply["result"].get("value")

    def wait_loaded(self, url, limit_s=60.0):
        """Wait until the open page is ``url`` and its document (with its images) has loaded
        (a new target starts as a loaded about:blank)."""
        deadline = time.monotonic() + limit_s
        check = f"location.href === {json.dumps(url)} && document.readyState === 'complete'"
        while not self.evaluate(check):
            assert time.monotonic() < deadline, "the page did not load"
            time.sleep(0.2)

    def close(self):
        os.killpg(self.pid, signal.SIGTERM)
        os.waitpid(self.pid, 0)
        os.close(self._in)
        os.close(self._out)
        shutil.rmtree(self._profile, ignore_errors=True)


