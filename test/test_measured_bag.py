"""``motoflex identify --measured BAG`` (issue 17): a rosbag2 folder read with rosbags.

- the CSV case written as bags (PoseArray per frame; one PointStamped or PoseStamped topic per
  marker; marker stamps later than the capture by the bench file's latency) gives the CSV's
  result exactly;
- the emulated rig's recording bags/example (loads as WrenchStamped, measured markers as
  PoseArray stamped at delivery, in bursts after a pause) identified with no FE model loaded
  gives the virtual identification's (bags/example/identification.json) values within their
  intervals.
"""
import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import yaml
from measured_cases import bench_yaml, hinge_record, verb_script

from motoflex_ros.formats.bench_file import load_bench
from motoflex_ros.formats.measured_csv import read_csv, write_csv
from motoflex_ros.identify.measured import identify_measured
from motoflex_ros.record.measured_bag import POINT, POSE, POSE_ARRAY, read_bag, write_bag

EXAMPLE = Path(__file__).resolve().parents[1] / "bags" / "example"


@pytest.fixture(scope="module")
def hinge(tmp_path_factory):
    folder = tmp_path_factory.mktemp("hinge")
    t, wrench, points, _, q0 = hinge_record(noise_m=5e-6)
    write_csv(folder / "rig.csv", t, wrench, points)
    (folder / "bench.yaml").write_text(bench_yaml("rig", q0, "from_data"))
    result = identify_measured(read_csv(folder / "rig.csv"), load_bench(folder / "bench.yaml"))
    return folder, (t, wrench, points, q0), result.to_dict()


def _same(a, b, path="result"):
    """Nested results equal, floats to 1e-9 relative (stamps in a bag are whole ns)."""
    if isinstance(a, dict):
        assert set(a) == set(b), path
        for key in a:
            _same(a[key], b[key], f"{path}.{key}")
    elif isinstance(a, list):
        assert len(a) == len(b), path
        for i, (x, y) in enumerate(zip(a, b)):
            _same(x, y, f"{path}[{i}]")
    elif isinstance(a, float) and b is not None:
        assert a == pytest.approx(b, rel=1e-9, abs=1e-12), path
    else:
        assert a == b, path


def _comparable(result):
    from motoflex_ros.formats.json_yaml import to_jsonable
    out = to_jsonable(result)
    out["measured"].pop("source")
    out["measured"]["counts"] = {k: v for k, v in out["measured"]["counts"].items()
                                 if k in ("frames", "dropped_marker_frames", "unmatched_frames")}
    return out


@pytest.mark.parametrize("layout", [POSE_ARRAY, POINT, POSE])
def test_bag_of_the_csv_case_gives_the_csv_result(hinge, tmp_path, layout):
    folder, (t, wrench, points, q0), expected = hinge
    topics = (["/rig/markers"] if layout == POSE_ARRAY else
              [f"/mocap/m{i + 1}" for i in range(points.shape[1])])
    write_bag(tmp_path / "bag", t, wrench, t, points, "/rig/wrench", topics, layout)
    bench = load_bench(folder / "bench.yaml")
    data = read_bag(tmp_path / "bag", bench, "/rig/wrench", topics)
    assert data.row_unit == "message"
    _same(_comparable(identify_measured(data, bench).to_dict()), _comparable(expected))


def test_bag_latency_and_default_topics(hinge, tmp_path):
    """Markers stamped 3 ms after their capture, the bench file says so: the same result.
    The bag's only WrenchStamped and PoseArray topics are taken without options."""
    folder, (t, wrench, points, q0), expected = hinge
    write_bag(tmp_path / "bag", t, wrench, t + 0.003, points, "/ati/wrench", ["/vicon/m"])
    (tmp_path / "bench.yaml").write_text(bench_yaml("rig", q0, "from_data", latency_s=0.003))
    bench = load_bench(tmp_path / "bench.yaml")
    data = read_bag(tmp_path / "bag", bench)
    result = identify_measured(data, bench).to_dict()
    for model in ("static", "bending"):
        for key in ("l", "beta", "b", "k", "J", "c"):
            if key in result[model]:
                assert result[model][key] == pytest.approx(expected[model][key], rel=1e-9)


def test_bag_problems_name_the_topic_and_message(hinge, tmp_path):
    from motoflex_ros.identify.measurements import MeasurementError
    folder, (t, wrench, points, q0), _ = hinge
    bad = points.copy()
    bad[7, 2, 1] = np.nan
    write_bag(tmp_path / "bag", t, wrench, t, bad, "/rig/wrench", ["/rig/markers"])
    bench = load_bench(folder / "bench.yaml")
    with pytest.raises(MeasurementError, match=r"/rig/markers: message 8, column "
                                               r"'poses\[2\].position.y'"):
        read_bag(tmp_path / "bag", bench)
    with pytest.raises(MeasurementError, match="no topic /nothing"):
        read_bag(tmp_path / "bag", bench, "/nothing")


def _agree(mine, theirs, key):
    half = [0.5 * (m["ci"][key][1] - m["ci"][key][0]) for m in (mine, theirs)
            if m["ci"][key][0] is not None]
    return abs(mine[key] - theirs[key]) <= max(half)


@pytest.mark.skipif(not (EXAMPLE / "metadata.yaml").exists(), reason="bags/example absent")
def test_emulated_rig_bag_without_the_fe_model(tmp_path):
    """bags/example's frame through the measured mode, the structures package blocked."""
    virtual = json.loads((EXAMPLE / "identification.json").read_text())["frame"]
    from motoflex_ros.bench.sensor import DEFAULT_MARKERS
    from motoflex_ros.formats.component_file import load_component  # here, not in the child
    q0 = load_component("frame").clamped_reduced().q0.tolist()
    (tmp_path / "bench.yaml").write_text(yaml.safe_dump({
        "bench": "frame", "loaded_end": [float(v) for v in q0],
        "markers": [list(m) for m in DEFAULT_MARKERS],
        "sensor": {"noise_m": 5e-6, "latency_s": 0.001}}))
    script = verb_script(["--measured", EXAMPLE, "--bench", tmp_path / "bench.yaml", "--json"])
    run = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    result = json.loads(run.stdout)["frame"]
    for model in ("static", "torsion", "bending"):
        for key in ("l", "beta", "b", "k", "J"):
            if key in virtual[model]:
                assert _agree(result[model], virtual[model], key), (model, key)
    for label in ("torsion", "bending"):
        # c: the measured decay's zeta (the virtual run used the model's 0.01); within the
        # measured interval, which carries the decay's
        lo, hi = result[label]["ci"]["c"]
        c_virtual = (2 * virtual["modal"][label]["zeta_decay"] * virtual[label]["J"]
                     * virtual["modal"][label]["omega_n"])
        assert lo <= c_virtual <= hi, label
    for key in ("k_t", "k_b"):
        half = 0.5 * (virtual["ci"][key][1] - virtual["ci"][key][0])
        assert abs(result[key] - virtual[key]) <= half, key
    counts = result["measured"]["counts"]
    assert counts["dropped_marker_frames"] == 0 and counts["frames"] > 4200
