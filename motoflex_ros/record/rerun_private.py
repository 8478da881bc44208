"""Run the rerun binary without touching the user's rerun configuration.

Every rerun command (the viewer, ``rerun rrd verify``, even ``rerun analytics config``) loads
its analytics configuration from ``$XDG_CONFIG_HOME/rerun/analytics.json`` and, on a first run,
writes it there with analytics on (and a pending event under ``$XDG_DATA_HOME``); ``rerun
analytics disable`` rewrites it. So that ``motoflex`` neither sends usage data nor changes the
user's settings without asking, its rerun children get a configuration folder of their own,
made by rerun itself with analytics off, removed afterwards. The viewer's other state (window
layout, under ``$XDG_DATA_HOME``) stays the user's.
"""
import os
import subprocess
import tempfile
from contextlib import contextmanager
from pathlib import Path

__all__ = ["private_rerun_env"]


@contextmanager
def private_rerun_env(rerun, base=None):
    """An environment (dict) for children running the rerun binary ``rerun``: analytics off
    in a temporary configuration folder; the user's ~/.config/rerun is neither read nor
    written. ``base``: the environment to start from (default os.environ)."""
    with tempfile.TemporaryDirectory(prefix="motoflex-rerun-") as folder:
        config, data = Path(folder) / "config", Path(folder) / "data"
        env = dict(base if base is not None else os.environ, XDG_CONFIG_HOME=str(config))
        subprocess.run([rerun, "analytics", "disable"], capture_output=True, timeout=60,
                       env=dict(env, XDG_DATA_HOME=str(data)), check=False)
        yield env
