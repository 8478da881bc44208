"""The identification node in ``mode: measured`` on live topics (issue 17).

A rig's publisher (test/measured_publisher.py, a process of its own) sends the hinge record of
test/measured_cases.py as a real rig would: the load cell at 400 Hz on its own clock (samples
offset from the markers', each stamped up to +-1 ms off the instant it was taken: stamp
jitter; at 400 Hz the stamps still increase), the marker sets at 1 kHz with 1 % of the frames
dropped, the two streams sent out of step (each message's send time jittered by +-1 ms, so that
loads and markers arrive interleaved in another order than their stamps). The
node (its own ROS domain, no acknowledgements, no FE model) identifies when asked and must give
the offline identification of the full record within its intervals, and count the dropped
frames exactly. No timing is asserted; the waits have no deadline but the hang guard.
"""
import json
import os
import signal
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("rclpy")

from measured_cases import bench_yaml, hinge_record  # noqa: E402

from motoflex_ros.formats.bench_file import load_bench  # noqa: E402
from motoflex_ros.formats.measured_csv import read_csv, write_csv  # noqa: E402
from motoflex_ros.identify.measured import identify_measured  # noqa: E402
from motoflex_ros.launcher.domain import DomainLock  # noqa: E402
from motoflex_ros.launcher.graph import ros_env  # noqa: E402

HANG_GUARD_S = 600.0
HERE = Path(__file__).resolve().parent


def _streams(t, wrench, points, rng):
    """Load cell at 400 Hz (its first sample 0.37 ms after the markers' clock start, stamps
    jittered by +-1 ms), 1 % of the marker frames dropped, send times jittered by +-1 ms."""
    taken = np.arange(t[0] + 0.00037, t[-1], 1.0 / 400.0)
    load = np.column_stack([np.interp(taken, t, wrench[:, k]) for k in range(6)])
    load_t = taken + rng.uniform(-1e-3, 1e-3, len(taken))
    assert np.all(np.diff(load_t) > 0)
    keep = rng.random(len(t)) >= 0.01
    keep[:5] = keep[-5:] = True
    marker_t = t[keep]
    send_t = np.r_[load_t, marker_t] + rng.uniform(-1e-3, 1e-3, len(load_t) + len(marker_t))
    return {"load_t": load_t, "wrench": load, "marker_t": marker_t, "markers": points[keep],
            "send_t": send_t}, int(np.sum(~keep))


LAYOUTS = {
    "posearray": (),
    # one PointStamped topic per marker, set by parameters; the load cell's topic remapped
    "points": ("-p", "marker_msg:=PointStamped", "-p", "markers_topic:=/vicon/rig", "-p",
               "n_markers:=4", "-r", "/bench/rig/load:=/ati/wrench"),
}


@pytest.mark.parametrize("layout", sorted(LAYOUTS))
def test_live_asynchronous_rig(tmp_path, layout):
    t, wrench, points, _, q0 = hinge_record(noise_m=5e-6)
    write_csv(tmp_path / "rig.csv", t, wrench, points)
    bench_path = tmp_path / "bench.yaml"
    bench_path.write_text(bench_yaml("rig", q0, "from_data"))
    offline = identify_measured(read_csv(tmp_path / "rig.csv"), load_bench(bench_path))
    offline = json.loads(json.dumps(offline.to_dict(), default=float))
    streams, dropped = _streams(t, wrench, points, np.random.default_rng(7))
    np.savez(tmp_path / "streams.npz", **streams)
    out = tmp_path / "live.json"
    with DomainLock() as lock:
        env = ros_env(lock.domain_id, tmp_path / "log")
        env["PYTHONPATH"] = os.pathsep.join([str(HERE.parent), str(HERE),
                                             env.get("PYTHONPATH", "")])
        node = subprocess.Popen(
            [sys.executable, "-m", "motoflex_ros.nodes.identification", "--ros-args",
             "-p", "mode:=measured", "-p", f"bench_file:={bench_path}", "-p",
             f"result_file:={out}", "-p", "exit_when_done:=true", "-p", "qos:=reliable",
             "-p", "use_sim_time:=false", *LAYOUTS[layout]],
            env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        rig = subprocess.Popen([sys.executable, str(HERE / "measured_publisher.py"),
                                str(tmp_path / "streams.npz"), "rig", layout], env=env,
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        try:
            rig_out = rig.communicate(timeout=HANG_GUARD_S)
            node_out = node.communicate(timeout=HANG_GUARD_S)
        finally:
            for proc in (rig, node):
                if proc.poll() is None:
                    os.kill(proc.pid, signal.SIGKILL)
                    proc.communicate()
    assert rig.returncode == 0, rig_out
    assert node.returncode == 0, node_out
    live = json.loads(out.read_text())["rig"]
    counts = live["measured"]["counts"]
    assert counts["dropped_marker_frames"] == dropped > 50
    assert counts["marker_frames"] == len(streams["marker_t"])
    assert counts["load_samples"] == len(streams["load_t"])
    assert "dropped" in node_out[1] and f"dropped {dropped} marker frames" in node_out[1]
    for model in ("static", "bending"):
        for key in ("l", "beta", "b", "k", "J", "c"):
            if key not in offline[model]:
                continue
            half = max(0.5 * (m[model]["ci"][key][1] - m[model]["ci"][key][0])
                       for m in (live, offline))
            assert abs(live[model][key] - offline[model][key]) <= half, (model, key)
    assert live["modal"]["bending"]["source"] == "free decay"
    assert live["modal"]["bending"]["omega_n"] == pytest.approx(
        offline["modal"]["bending"]["omega_n"], rel=1e-3)


@pytest.mark.parametrize("params, words", [
    ((), "parameter 'bench_file' is required in mode measured"),
    (("bench_file:=/nonexistent/bench.yaml",), "/nonexistent/bench.yaml: file not found"),
])
def test_measured_node_refuses_a_missing_bench_file(tmp_path, params, words):
    with DomainLock() as lock:
        env = ros_env(lock.domain_id, tmp_path / "log")
        cmd = [sys.executable, "-m", "motoflex_ros.nodes.identification", "--ros-args",
               "-p", "mode:=measured"]
        for p in params:
            cmd += ["-p", p]
        proc = subprocess.run(cmd, env=env, capture_output=True, text=True,
                              timeout=HANG_GUARD_S)
    assert proc.returncode == 2, proc
    assert words in proc.stderr and "Traceback" not in proc.stderr
