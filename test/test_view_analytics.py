"""`motoflex view` does not write the user's rerun configuration (issue 16, point 8).

It used to run `rerun analytics config` and `rerun analytics disable` in the user's own
environment: the first creates ~/.config/rerun/analytics.json (analytics on, plus a pending
event under ~/.local/share/rerun) when there is none, the second rewrites it. Here the user's
home is a temporary folder; the web viewer is started and stopped, and the user's rerun files
are compared before and after.
"""
import json
import os
import subprocess
import sys
from pathlib import Path

import pytest
from processes import processes_naming

from motoflex_ros.record.rerun_private import private_rerun_env
from motoflex_ros.record.rerun_readback import rerun_executable


def _user_env(home):
    return dict(os.environ, HOME=str(home), XDG_CONFIG_HOME=str(home / ".config"),
                XDG_DATA_HOME=str(home / ".local" / "share"))


def _rerun_files(home):
    """{relative path: bytes} of every rerun file in the user's home."""
    return {str(p.relative_to(home)): p.read_bytes() for p in home.rglob("*")
            if p.is_file() and "rerun" in p.parts}


@pytest.fixture()
def recording(tmp_path):
    import rerun as rr
    folder = tmp_path / "run1"
    folder.mkdir()
    rec = rr.RecordingStream("motoflex_test")
    rec.save(str(folder / "run1.rrd"))
    rec.log("value", rr.Scalars(1.0))
    rec.flush()
    rec.disconnect()
    return folder


def _serve_and_stop(folder, env):
    view = subprocess.Popen([sys.executable, "-m", "motoflex_ros.cli.main", "view", str(folder),
                             "--web"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            env=env)
    viewer = []
    try:
        line = view.stdout.readline()
        assert "http://127.0.0.1:" in line, view.stderr.read()[-2000:]
        # the rerun binary reads the recording from its stdin: its command line names no file
        viewer = Path(f"/proc/{view.pid}/task/{view.pid}/children").read_text().split()
        assert viewer
    finally:
        view.terminate()   # at once, while view may still be printing its second line
        view.wait(timeout=60)
    # its viewer went with it (a SIGTERM between the address and the try/finally once left the
    # rerun binary running, orphaned, at half a core, in every suite run)
    assert not processes_naming(folder)
    assert not [pid for pid in viewer if Path(f"/proc/{pid}").exists()]



USER_CONFIG = {"analytics_enabled": True, "analytics_id": "0123456789abcdef", "metadata": {},
               "config_file_path": "", "data_dir_path": ""}


@pytest.mark.parametrize("existing", [False, True], ids=["no-config", "own-config"])
def test_view_leaves_the_users_rerun_configuration_alone(tmp_path, recording, existing):
    home = tmp_path / "home"
    config = home / ".config" / "rerun" / "analytics.json"
    if existing:    # analytics on, as the user chose: must stay so, byte for byte
        config.parent.mkdir(parents=True)
        config.write_text(json.dumps({**USER_CONFIG, "config_file_path": str(config),
                                      "data_dir_path": str(home / "data")}))
    home.mkdir(exist_ok=True)
    before = _rerun_files(home)
    _serve_and_stop(recording, _user_env(home))
    assert _rerun_files(home) == before


def test_private_environment_has_analytics_off_outside_the_users_home(tmp_path):
    home = tmp_path / "home"
    home.mkdir()
    rerun = rerun_executable()
    with private_rerun_env(rerun, _user_env(home)) as env:
        shown = subprocess.run([rerun, "analytics", "config"], capture_output=True, text=True,
                               env=env, timeout=60)
        folder = env["XDG_CONFIG_HOME"]
    config = json.loads(shown.stdout)
    assert config["analytics_enabled"] is False
    assert config["config_file_path"].startswith(folder)
    assert str(home) not in config["config_file_path"]
    assert _rerun_files(home) == {}
    assert not os.path.exists(folder)    # removed afterwards
