"""Logs and CLI messages (issue 24, point 9): progress bars in logs, the campaign bar's total,
wall times, speeds in the user's unit, flag help, .rrd suffix, the viewer without a display
and its gRPC address."""
import io
import re
import subprocess
from pathlib import Path

import pytest

from motoflex_ros.cli.main import build_parser, main
from motoflex_ros.progress import LogLines, progress_bar

ROOT = Path(__file__).resolve().parents[1]


class _Terminal(io.StringIO):
    def isatty(self):
        return True


def test_progress_in_a_log_is_a_line_per_ten_percent():
    log = io.StringIO()
    with progress_bar(total=150, desc="campaign", unit="step", file=log) as bar:
        for _ in range(150):
            bar.update(1)
    text = log.getvalue()
    assert "\r" not in text
    lines = text.splitlines()
    # 0 %, 10 %, ..., 100 %: one line each, the last one complete
    assert [int(re.search(r"(\d+)%", line).group(1)) for line in lines] == list(range(0, 101, 10))
    assert lines[-1].startswith("campaign: 100%") and "150/150" in lines[-1]


def test_progress_on_a_terminal_is_tqdms_live_bar():
    screen = _Terminal()
    with progress_bar(total=3, desc="x", file=screen) as bar:
        bar.update(3)
    assert not isinstance(bar, LogLines) and "\r" in screen.getvalue()


def test_progress_of_an_iterable_in_a_log_ends_with_its_last_line_once():
    log = io.StringIO()
    assert list(progress_bar(range(4), desc="report", file=log)) == [0, 1, 2, 3]
    lines = log.getvalue().splitlines()
    assert lines[-1].startswith("report: 100%") and sum("100%" in line for line in lines) == 1


def test_progress_disabled_writes_nothing(capsys):
    with progress_bar(total=5, desc="x", enabled=False) as bar:
        bar.update(5)
    assert capsys.readouterr().err == ""


def test_campaign_bar_counts_tests_with_a_fixed_total(monkeypatch):
    """The campaign's bar runs over bench tests (a total known before the run); the old one ran
    over the longest planned simulated time and shrank to the time the run took at its end."""
    pytest.importorskip("rclpy")
    from types import SimpleNamespace

    from motoflex_ros.launcher.campaign_graph import planned_run
    from motoflex_ros.launcher.monitor import Monitor, _progress_bar
    duration_s, tests = planned_run(["tube"])
    assert tests >= 2 and duration_s > 0
    log = io.StringIO()
    monkeypatch.setattr("sys.stderr", log)
    bar = _progress_bar(duration_s, tests)
    state = SimpleNamespace(tests_done={}, sim_ns=0)
    for done in range(tests + 1):
        state.tests_done["tube"], state.sim_ns = done, done * 10**9
        Monitor._show(state, bar, tests)
        assert bar.total == tests and bar.n == done
    bar.close()
    assert f"{tests}/{tests} tests, simulated {tests:.1f} s" in log.getvalue().splitlines()[-1]


def test_campaign_wall_times_say_what_they_cover():
    from motoflex_ros.cli.campaign import _wall_times
    line = _wall_times(59.94, 154.0)
    assert "154.0 s for the whole command" in line and "node graph 59.9 s" in line


@pytest.mark.parametrize("args, said", [
    (["--speeds-kmh", "-5"], "got -5 km/h"),
    (["--speeds-kmh", "500"], "got 500 km/h"),
    (["--speeds-ms", "-2"], "got -2 m/s"),
    (["--range-kmh", "-10", "40", "--step-kmh", "5"], "got -10 km/h"),
])
def test_eig_speed_errors_in_the_users_unit(capsys, args, said):
    assert main(["eig", "--vehicle", "touring", *args]) == 2
    err = capsys.readouterr().err
    assert said in err and "1.38889" not in err, err


def _help_of(verb, option):
    parser = build_parser()
    sub = next(a for a in parser._actions if a.dest == "verb").choices[verb]
    return next(a.help for a in sub._actions if option in a.option_strings)


def test_flags_show_no_default_in_help():
    assert "default" not in _help_of("report", "--no-compute")
    assert "(default: 0)" in _help_of("campaign", "--seed") or "default 0" in _help_of(
        "campaign", "--seed")


def test_rerun_out_must_be_an_rrd(tmp_path, capsys):
    out = tmp_path / "x.txt"
    assert main(["rerun", str(ROOT / "bags" / "example"), "--out", str(out)]) == 2
    assert "ends in .rrd" in capsys.readouterr().err and not out.exists()


def test_view_without_a_display_says_so(monkeypatch, capsys):
    for name in ("DISPLAY", "WAYLAND_DISPLAY", "WAYLAND_SOCKET"):
        monkeypatch.delenv(name, raising=False)
    assert main(["view", str(ROOT / "bags" / "example")]) == 2
    err = capsys.readouterr().err
    assert "no display" in err and "--web" in err and "winit" not in err


def test_native_viewer_grpc_listens_on_loopback_only(tmp_path):
    """The command ``view`` starts: rerun's native viewer starts its gRPC server before it
    opens a window (which fails here, without a display) and says where it listens."""
    import rerun as rr

    from motoflex_ros.cli.view import free_port, native_command
    from motoflex_ros.record.rerun_private import private_rerun_env
    from motoflex_ros.record.rerun_readback import rerun_executable
    rrd = tmp_path / "run.rrd"
    rec = rr.RecordingStream("motoflex_test")
    rec.save(str(rrd))
    rec.log("value", rr.Scalars(1.0))
    rec.flush()
    rec.disconnect()
    rerun, port = rerun_executable(), free_port()
    with private_rerun_env(rerun) as env:
        for name in ("DISPLAY", "WAYLAND_DISPLAY", "WAYLAND_SOCKET"):
            env.pop(name, None)
        run = subprocess.run(native_command(rerun, rrd, port), env=env, capture_output=True,
                             text=True, timeout=60)
    said = run.stdout + run.stderr
    assert f"Listening for gRPC connections on 127.0.0.1:{port}" in said, said[-2000:]
    assert "0.0.0.0" not in said
