"""``motoflex replay BAG --rate R``: recording order and count kept, pacing scales with 1/R.

A bag is written here with known log times (1.2 s: /clock every 25 ms, a text topic every 50 ms,
interleaved). A probe node on a private domain (localhost discovery) subscribes to both topics
and announces itself on /rig/ready once it sees the replay's publishers; ``--wait-for probe``
holds the replay until then, so no message is missed. Checks: every topic's messages arrive
complete, with the recorded contents and in the recording's order, at both rates; the span
between the first and the last message received is at least half the paced 1.2 s / R and the
replay at
rate 0.5 takes at least 1.5 times as long as at rate 2 (4x scheduled). Only lower bounds: a
loaded machine may slow a replay down, never speed it up.
"""
import os
import subprocess
import sys
import time

import pytest

pytest.importorskip("rclpy")
from rclpy.serialization import deserialize_message, serialize_message  # noqa: E402
from rosgraph_msgs.msg import Clock  # noqa: E402
from std_msgs.msg import String  # noqa: E402

from motoflex_ros.launcher.domain import DomainLock  # noqa: E402
from motoflex_ros.launcher.graph import ros_env  # noqa: E402
from motoflex_ros.launcher.status import write_status  # noqa: E402
from motoflex_ros.nodes.stamps import time_msg  # noqa: E402
from motoflex_ros.record.mcap_bag import BagWriter, read_messages  # noqa: E402

DURATION_S = 1.2
MATCH_GRACE_S = 0.5
TOPICS = {"/clock": "rosgraph_msgs/msg/Clock", "/probe/text": "std_msgs/msg/String"}


def write_bag(path):
    """/clock every 25 ms and a numbered String every 50 ms over DURATION_S, log time 10 s on."""
    start = 10**10
    with BagWriter(path) as writer:
        for topic, type_name in TOPICS.items():
            writer.add_topic(topic, type_name)
        for k in range(round(DURATION_S / 0.025) + 1):
            t_ns = start + k * 25_000_000
            writer.write("/clock", t_ns, bytes(serialize_message(Clock(clock=time_msg(t_ns)))))
            if k % 2 == 0:
                writer.write("/probe/text", t_ns, bytes(serialize_message(String(data=f"m{k}"))))
    write_status(path, "complete")   # as a finished run leaves it (replay refuses others)
    return path


class Probe:
    """Raw subscriptions on the bag's topics and a ready announcement, on one domain."""

    def __init__(self, domain_id):
        import rclpy
        from rclpy.executors import SingleThreadedExecutor

        from motoflex_ros.nodes.interfaces import READY_TOPIC
        from motoflex_ros.nodes.qos_profiles import latched_qos, reliable_qos
        self.context = rclpy.Context()
        rclpy.init(args=[], context=self.context, domain_id=domain_id)
        self.node = rclpy.create_node("probe", context=self.context)
        self.received = []
        for topic in TOPICS:
            msg_type = Clock if topic == "/clock" else String
            self.node.create_subscription(msg_type, topic, self._keep(topic), reliable_qos(),
                                          raw=True)
        self.ready_pub = self.node.create_publisher(String, READY_TOPIC, latched_qos())
        self.executor = SingleThreadedExecutor(context=self.context)
        self.executor.add_node(self.node)
        self.announced, self.seen_at = False, None

    def _keep(self, topic):
        return lambda data: self.received.append((time.monotonic(), topic, bytes(data)))

    def spin(self):
        """Spin; announce once the replay's publishers have been seen for MATCH_GRACE_S (the
        writers' side of the match completes shortly after the readers' side)."""
        self.executor.spin_once(timeout_sec=0.01)
        if self.announced:
            return
        if self.seen_at is None and all(self.node.count_publishers(t) for t in TOPICS):
            self.seen_at = time.monotonic()
        if self.seen_at is not None and time.monotonic() - self.seen_at > MATCH_GRACE_S:
            self.ready_pub.publish(String(data="probe"))
            self.announced = True

    def close(self):
        import rclpy
        self.executor.shutdown()
        self.node.destroy_node()
        rclpy.shutdown(context=self.context)


def replay(bag, rate, domain_id, log_dir, expected):
    """Replay ``bag`` at ``rate`` into a fresh probe; returns [(t, topic, data)] received."""
    probe = Probe(domain_id)
    try:
        proc = subprocess.Popen([sys.executable, "-m", "motoflex_ros.cli.main", "replay",
                                 str(bag), "--rate", str(rate), "--wait-for", "probe"],
                                env=ros_env(domain_id, log_dir), text=True,
                                stdout=subprocess.PIPE, stderr=subprocess.PIPE)
        deadline = time.monotonic() + 60.0
        while (proc.poll() is None or len(probe.received) < expected) \
                and time.monotonic() < deadline:
            probe.spin()
            if proc.poll() not in (None, 0):
                break
        out, err = proc.communicate(timeout=30)
        assert proc.returncode == 0, err
        counts = {t: sum(m[1] == t for m in probe.received) for t in TOPICS}
        assert len(probe.received) == expected, (rate, counts, out, err)
        return probe.received
    finally:
        if proc.poll() is None:
            os.kill(proc.pid, 9)
        probe.close()


def by_topic(messages):
    """{topic: [content]}: clock times [ns] and texts (CDR padding may differ on the wire)."""
    out = {}
    for _, topic, data in messages:
        if topic == "/clock":
            clock = deserialize_message(data, Clock).clock
            content = clock.sec * 10**9 + clock.nanosec
        else:
            content = deserialize_message(data, String).data
        out.setdefault(topic, []).append(content)
    return out


def test_replay_rate_keeps_order_and_scales_duration(tmp_path, monkeypatch):
    monkeypatch.setenv("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")
    monkeypatch.delenv("ROS_LOCALHOST_ONLY", raising=False)
    bag = write_bag(tmp_path / "short")
    recorded = by_topic((m.log_time_ns, m.topic, bytes(m.data)) for m in read_messages(bag))
    count = sum(map(len, recorded.values()))
    assert count == 49 + 25
    spans = {}
    with DomainLock() as lock:
        for rate in (2.0, 0.5):
            got = replay(bag, rate, lock.domain_id, tmp_path / f"log{rate}", count)
            assert by_topic(got) == recorded, rate          # complete, in recording order
            spans[rate] = got[-1][0] - got[0][0]
            assert spans[rate] >= 0.5 * DURATION_S / rate, spans
    assert spans[0.5] >= 1.5 * spans[2.0], spans
