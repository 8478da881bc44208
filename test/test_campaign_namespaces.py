"""Two rigs in one ROS domain at once, under /rig_a and /rig_b (issue 16, point 5).

Every topic of a node is relative, so ``motoflex campaign --namespace /rig_a`` moves the whole
graph under /rig_a; the two runs share one ROS_DOMAIN_ID (each rig accepts only its own run's
publishers, so topics that met would fail both runs) and each gives the results of a solo run
(the offline campaign, which test_campaign_graph shows a solo graph run equals), with a bag
named as a solo run's (the recorder names its rig's topics from the rig's root).
"""
import json
import os
import re
import subprocess
import sys

import pytest

pytest.importorskip("rclpy")
from test_campaign_graph import (  # noqa: E402
    COMPONENT,
    SHORT_PROTOCOL,
    _assert_same,
    interruptible,
    offline_identification,
    without_inputs,
)

from motoflex_ros.launcher.domain import DomainLock  # noqa: E402
from motoflex_ros.record import mcap_bag  # noqa: E402


def test_two_namespaced_rigs_in_one_domain_equal_solo_runs(tmp_path):
    """On the short protocol (test/data/short_bench.yaml: every test kind, a few hundred
    samples): what is shown is the namespacing, not the paper's numbers."""
    with DomainLock() as free:
        domain = free.domain_id
    # hold the id shared (as a namespaced run does) so that no root-namespace run takes it
    with DomainLock(domain_id=domain, namespace="/test_holder"):
        env = dict(os.environ, TMPDIR=str(tmp_path), OPENBLAS_NUM_THREADS="1",
                   ROS_DOMAIN_ID=str(domain))
        runs = {ns: subprocess.Popen(
            [sys.executable, "-m", "motoflex_ros.cli.main", "campaign", "--component",
             COMPONENT, "--namespace", f"/{ns}", "--out", str(tmp_path / ns), "--report",
             "none", "--protocol", SHORT_PROTOCOL], env=env, text=True,
            stdout=subprocess.PIPE, stderr=subprocess.PIPE,
            preexec_fn=interruptible) for ns in ("rig_a", "rig_b")}
        outputs = {ns: proc.communicate(timeout=900) for ns, proc in runs.items()}
    offline = offline_identification(SHORT_PROTOCOL)
    for ns, proc in runs.items():
        _, err = outputs[ns]
        assert proc.returncode == 0, err
        said = re.search(r"ROS_DOMAIN_ID (\d+) \(from ROS_DOMAIN_ID\), namespace /(\w+)", err)
        assert said and said.groups() == (str(domain), ns), err
        _assert_same(without_inputs(json.loads((tmp_path / ns / "identification.json")
                                               .read_text())), offline)
        topics = {t.name for t in mcap_bag.bag_info(tmp_path / ns).topics}
        assert f"/bench/{COMPONENT}/load" in topics and "/tf_static" in topics
        assert not any(t.startswith(("/rig_a", "/rig_b")) for t in topics), topics
