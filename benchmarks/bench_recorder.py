"""Recorder throughput and campaign wall time.

    python benchmarks/bench_recorder.py [--messages N] [--campaign]

1. recorder: two publisher processes send N pre-serialized WrenchStamped messages (raw bytes,
   reliable keep-all) on 4 topics to the recorder node (a separate process); the rate is the
   recorded count over the span of receive times in the bag, and per CPU-second of the
   recorder process (independent of how busy the shared machine is). Baseline in the same
   run: the bag writer alone (record.mcap_bag, no ROS) writing the same messages; the ratio
   shows what the middleware costs. Target: >= 20,000 messages/s. Also rosbags' rosbag2
   Writer (MCAP, zstd) alone on the same messages, the alternative to record.mcap_bag.
2. --campaign: ``motoflex campaign`` (all components, through the graph) wall time against the
   offline ``identify_components`` of the same components in this process. Target: <= 30 s.
"""
import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

TOPICS = [f"/bench/load_{i}" for i in range(4)]

PUBLISHER = r"""
import sys, time, rclpy, rclpy.duration
from geometry_msgs.msg import WrenchStamped
from rclpy.serialization import serialize_message
from motoflex_ros.nodes.qos_profiles import reliable_qos
from motoflex_ros.nodes.transport import publish_patiently
rclpy.init()
node = rclpy.create_node("bench_publisher")
topics, n = sys.argv[1].split(","), int(sys.argv[2])
pubs = [node.create_publisher(WrenchStamped, t, reliable_qos()) for t in topics]
while any(p.get_subscription_count() == 0 for p in pubs):
    time.sleep(0.05)
time.sleep(0.5)
msg = WrenchStamped()
data = []
for i in range(n):
    msg.wrench.force.y = float(i)
    data.append(serialize_message(msg))
for i, raw in enumerate(data):
    publish_patiently(pubs[i % len(pubs)], raw)
for pub in pubs:
    pub.wait_for_all_acked(rclpy.duration.Duration(seconds=60))
"""


def _baseline(n, tmp):
    from geometry_msgs.msg import WrenchStamped
    from rclpy.serialization import serialize_message

    from motoflex_ros.record.mcap_bag import BagWriter
    msg = WrenchStamped()
    start = time.perf_counter()
    with BagWriter(Path(tmp) / "baseline") as writer:
        for t in TOPICS:
            writer.add_topic(t, "geometry_msgs/msg/WrenchStamped")
        for i in range(n):
            msg.wrench.force.y = float(i)
            writer.write(TOPICS[i % len(TOPICS)], time.time_ns(), serialize_message(msg))
    return n / (time.perf_counter() - start)


def _rosbags_writer(n, tmp):
    from geometry_msgs.msg import WrenchStamped
    from rclpy.serialization import serialize_message
    from rosbags.rosbag2 import CompressionFormat, CompressionMode, StoragePlugin, Writer
    from rosbags.typesys import Stores, get_typestore
    store = get_typestore(Stores.ROS2_JAZZY)
    msg = WrenchStamped()
    start = time.perf_counter()
    writer = Writer(Path(tmp) / "rosbags", version=9, storage_plugin=StoragePlugin.MCAP)
    writer.set_compression(CompressionMode.STORAGE, CompressionFormat.ZSTD)
    writer.open()
    connections = [writer.add_connection(t, "geometry_msgs/msg/WrenchStamped",
                                         typestore=store) for t in TOPICS]
    for i in range(n):
        msg.wrench.force.y = float(i)
        writer.write(connections[i % len(TOPICS)], time.time_ns(), serialize_message(msg))
    writer.close()
    return n / (time.perf_counter() - start)


def _recorder_rate(n, tmp):
    from motoflex_ros.launcher.domain import DomainLock
    from motoflex_ros.launcher.graph import ros_env
    from motoflex_ros.record.mcap_bag import bag_info, read_messages
    from motoflex_ros.units import NS_PER_S
    bag = Path(tmp) / "recorded"
    with DomainLock() as lock:
        env = ros_env(lock.domain_id, Path(tmp) / "log")
        recorder = subprocess.Popen(
            [sys.executable, "-m", "motoflex_ros.nodes.recorder", "--ros-args", "-p",
             f"bag:={bag}", "-p", f"topics:={TOPICS!r}"], env=env)
        time.sleep(3.0)  # let the recorder start up before its CPU clock is read
        cpu_start = _cpu_seconds(recorder.pid)
        half = [",".join(TOPICS[:2]), ",".join(TOPICS[2:])]
        publishers = [subprocess.Popen([sys.executable, "-c", PUBLISHER, topics, str(n // 2)],
                                       env=env) for topics in half]
        codes = [p.wait(600) for p in publishers]
        time.sleep(1.0)
        cpu = _cpu_seconds(recorder.pid) - cpu_start
        recorder.send_signal(2)
        recorder.wait(60)
    assert codes == [0, 0] and recorder.returncode == 0
    info = bag_info(bag)
    times = [m.log_time_ns for m in read_messages(bag)]
    return (info.message_count, info.message_count / ((max(times) - min(times)) / NS_PER_S),
            info.message_count / cpu)


def _cpu_seconds(pid):
    """User + system CPU time [s] of a process (Linux /proc)."""
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def _campaign(tmp):
    from motoflex_ros.bench.offline_campaign import identify_components
    from motoflex_ros.formats.component_file import load_components
    from motoflex_ros.launcher.campaign_graph import run_campaign_graph
    components = ["frame", "front_assembly", "swingarm"]
    start = time.perf_counter()
    identify_components(load_components(components), seed=0)
    offline = time.perf_counter() - start
    start = time.perf_counter()
    outcome = run_campaign_graph(components, Path(tmp) / "campaign", seed=0)
    graph = time.perf_counter() - start
    return offline, graph, outcome


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--messages", type=int, default=60_000)
    parser.add_argument("--campaign", action="store_true")
    args = parser.parse_args()
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
    with tempfile.TemporaryDirectory() as tmp:
        base = _baseline(args.messages, tmp)
        other = _rosbags_writer(args.messages, tmp)
        count, rate, per_cpu = _recorder_rate(args.messages, tmp)
        print(f"bag writer alone (baseline): {base:10,.0f} messages/s")
        print(f"rosbags' Writer alone:       {other:10,.0f} messages/s "
              f"(ratio {other / base:.2f} of baseline)")
        print(f"recorder node over DDS:      {rate:10,.0f} messages/s "
              f"({count} of {args.messages} recorded, ratio {rate / base:.2f} of baseline, "
              f"target 20,000)")
        print(f"recorder per CPU-second:     {per_cpu:10,.0f} messages/s of its own CPU time "
              f"(what one free core sustains; load average now {os.getloadavg()[0]:.1f})")
        if args.campaign:
            offline, graph, outcome = _campaign(tmp)
            print(f"campaign offline:            {offline:10.1f} s")
            print(f"campaign through the graph:  {graph:10.1f} s "
                  f"(ratio {graph / offline:.1f} of offline, target 30 s)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
