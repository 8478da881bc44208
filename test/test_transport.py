"""The ROS transport behind one interface (issue 25, point 3): both paths take the same
messages with their sequence numbers, the ctypes path with the publisher's GID and only on the
releases it was checked against, and a campaign on the plain path identifies what the ctypes
path identifies."""
import json

import pytest

pytest.importorskip("rclpy")
import rclpy  # noqa: E402
from rclpy.node import Node  # noqa: E402
from rclpy.serialization import serialize_message  # noqa: E402
from std_msgs.msg import String  # noqa: E402

from motoflex_ros.errors import MotoflexError  # noqa: E402
from motoflex_ros.launcher.domain import DomainLock  # noqa: E402
from motoflex_ros.nodes import endpoints, transport, transport_ctypes, transport_rclpy  # noqa: E402
from motoflex_ros.nodes.qos_profiles import reliable_qos  # noqa: E402

CHECKED = dict(transport_ctypes.CHECKED_VERSIONS)


def test_ctypes_path_refuses_other_releases_naming_them_and_the_switch():
    transport_ctypes.check_versions({**CHECKED, "rmw": "7.3.9"})   # a patch release: same ABI
    with pytest.raises(MotoflexError) as refused:
        transport_ctypes.check_versions({**CHECKED, "rmw": "7.8.1", "rclpy": None})
    text = str(refused.value)
    assert "rmw 7.8.1" in text and "rclpy not found" in text and "rcl 9.2.8" not in \
        text.split("this installation has")[1]
    assert "rmw 7.3.2" in text and "MOTOFLEX_TRANSPORT=rclpy" in text


def test_this_installation_is_the_checked_one():
    """The suite runs the ctypes path by default: it must be on the releases it names."""
    transport_ctypes.check_versions()
    assert transport.selected({}) is transport_ctypes


def test_switch_selects_the_plain_path_and_refuses_unknown_names():
    assert transport.selected({"MOTOFLEX_TRANSPORT": "rclpy"}) is transport_rclpy
    with pytest.raises(MotoflexError, match="expected one of ctypes, rclpy"):
        transport.selected({"MOTOFLEX_TRANSPORT": "zenoh"})


def test_node_refuses_to_start_on_unchecked_releases(monkeypatch, capsys):
    """Checked at start, before rclpy.init: one line naming the versions, exit code 2."""
    from motoflex_ros.nodes.node_main import run_node
    from motoflex_ros.nodes.sim_clock import SimClock
    monkeypatch.delenv("MOTOFLEX_TRANSPORT", raising=False)
    monkeypatch.setattr(transport_ctypes, "installed_versions",
                        lambda: {**CHECKED, "rcl": "10.0.0"})
    assert run_node(SimClock, ["sim_clock"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("sim_clock: error: the ctypes ROS transport") and "rcl 10.0.0" in err


@pytest.fixture
def context():
    with DomainLock() as lock:
        ctx = rclpy.Context()
        rclpy.init(args=[], context=ctx, domain_id=lock.domain_id)
        try:
            yield ctx
        finally:
            rclpy.try_shutdown(context=ctx)


@pytest.mark.ros
@pytest.mark.parametrize("path", ["ctypes", "rclpy"])
def test_both_paths_take_every_message_with_its_sequence_number(context, path):
    """40 raw String messages from one publisher: every one, in order, numbered 1..40, the
    ctypes path with the publisher's GID (the GID both paths give for the publisher)."""
    talker = Node("talker", context=context)
    listener = Node("listener", context=context)
    pub = talker.create_publisher(String, "probe", reliable_qos())
    got, seen = [], []
    sub = listener.create_subscription(String, "probe", got.append, reliable_qos(), raw=True)
    module = transport.TRANSPORTS[path]
    spinner = module.Spinner(listener, lambda s, gid, seq: seen.append((s, gid, seq)))
    gid = transport_ctypes.publisher_gid(pub)
    assert transport_rclpy.publisher_gid(pub, talker) == gid
    while pub.get_subscription_count() < 1:
        spinner.spin_once(0.05)
    sent = [serialize_message(String(data=f"m{k}")) for k in range(40)]
    for data in sent:
        transport.publish_patiently(pub, data)
    handled = 0
    while handled < len(sent):
        count = spinner.spin_once(1.0)
        assert count > 0, f"{handled} of {len(sent)} arrived"
        handled += count
    assert got == sent
    assert [seq for _, _, seq in seen] == list(range(1, 41))
    assert {s for s, _, _ in seen} == {sub}
    assert {g for _, g, _ in seen} == ({gid} if path == "ctypes" else {None})


@pytest.mark.ros
def test_plain_path_trust_check_reads_the_topics_publishers_in_the_graph(context, tmp_path,
                                                                          monkeypatch):
    """Without the sender of a message, a publisher the graph lists on the topic that none of
    the run's files names is foreign, before the message is used (after the wait a new
    publisher gets, none here); gaps counted while the topic has one publisher."""
    monkeypatch.setattr(endpoints, "NAME_WAIT_S", 0.0)
    listener = Node("listener", context=context)
    stray = Node("stray", context=context)
    sub = listener.create_subscription(String, "probe", lambda m: None, reliable_qos())
    own = endpoints.RunEndpoints(tmp_path, "talker")
    talker_pub = Node("talker", context=context).create_publisher(String, "probe",
                                                                  reliable_qos())
    own.register(talker_pub, transport_ctypes.publisher_gid(talker_pub))
    guard = endpoints.InputGuard(listener, endpoints.RunEndpoints(tmp_path, "listener"))
    while sub.get_publisher_count() < 1:
        rclpy.spin_once(listener, timeout_sec=0.05)
    guard.check(sub, None, 1)
    guard.check(sub, None, 4)   # 2 and 3 lost
    assert guard.gaps == 2
    stray.create_publisher(String, "probe", reliable_qos())
    while sub.get_publisher_count() < 2:
        rclpy.spin_once(listener, timeout_sec=0.05)
    with pytest.raises(endpoints.ForeignPublisher, match="node '/stray'"):
        guard.check(sub, None, 5)


@pytest.mark.ros
@pytest.mark.slow   # a short campaign of one component through the graph: about 15 s
def test_campaign_on_the_plain_path_identifies_as_the_ctypes_path(tmp_path):
    """``MOTOFLEX_TRANSPORT=rclpy``: the swingarm's campaign identifies exactly what the
    offline identification gives, which the ctypes graph gives to 1e-12
    (test_campaign_graph.py), and the bag holds every sample (a recorder that fell behind
    would lose its tail unnoticed). On the short protocol (test/data/short_bench.yaml: every
    test kind, so every message type, a few hundred samples): the point is the transport."""
    from test_campaign_graph import (
        COMPONENT,
        SHORT_PROTOCOL,
        _assert_same,
        _campaign,
        offline_identification,
        offline_runs,
        without_inputs,
    )

    from motoflex_ros.record import mcap_bag
    bag = tmp_path / "run"
    proc = _campaign(tmp_path, "--out", str(bag), "--report", "none",
                     "--protocol", SHORT_PROTOCOL, MOTOFLEX_TRANSPORT="rclpy")
    out, err = proc.communicate(timeout=600)
    assert proc.returncode == 0, err
    assert "ROS transport rclpy" in err
    live = without_inputs(json.loads((bag / "identification.json").read_text()))
    runs = offline_runs(SHORT_PROTOCOL)
    _assert_same(live, offline_identification(runs=runs))
    counts = {t.name: t.count for t in mcap_bag.bag_info(bag).topics}
    phases = counts[f"/bench/{COMPONENT}/phase"]   # every sample and the end marker
    assert phases == runs[COMPONENT][1].n_samples + 1   # the offline campaign's samples
    assert counts[f"/bench/{COMPONENT}/markers/measured"] == phases
    assert counts[f"/bench/{COMPONENT}/load"] == counts[f"/bench/{COMPONENT}/pose"] == phases - 1
