"""The two ROS transports of the nodes (motoflex_ros/nodes/transport.py) against each other.

    python benchmarks/bench_transport.py [--messages N] [--repeat R] [--no-graph] [--cdr]

1. message loop: a publisher process sends N pre-serialized std_msgs/String (200 characters,
   reliable keep-all); in this process one subscription takes them through each path's
   spinner with the trust check's callback; CPU microseconds of this thread per message. Also
   rclpy's executor alone (one ``spin_once`` per message, what the plain path would be
   without draining with ``take_message``).
2. bench graph (unless --no-graph): ``motoflex campaign --component swingarm --report none``
   with MOTOFLEX_TRANSPORT=ctypes and =rclpy, alternated R times: the node graph's wall time
   (the campaign's timings.json) and the CPU seconds of the campaign's whole process tree.

3. --cdr (alone): what the hand-written CDR of the bench's messages (motoflex_ros/nodes/cdr.py)
   and the hand-written quaternion (motoflex_ros/spatial.py) save against building message
   objects with rclpy's serializer and against scipy's Rotation: microseconds per call.

Prints the ratios plain/ctypes (measured in one run; absolute times drift 1.3-1.5x on this
shared machine).
"""
import argparse
import json
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

PUBLISHER = r"""
import sys, time, rclpy
from std_msgs.msg import String
from rclpy.serialization import serialize_message
from motoflex_ros.nodes.qos_profiles import reliable_qos
from motoflex_ros.nodes.transport import publish_patiently
rclpy.init()
node = rclpy.create_node("bench_talker")
pub = node.create_publisher(String, sys.argv[2], reliable_qos())
while pub.get_subscription_count() < 1:
    time.sleep(0.01)
time.sleep(0.5)
raw = serialize_message(String(data="x" * 200))
for _ in range(int(sys.argv[1])):
    publish_patiently(pub, raw)
pub.wait_for_all_acked()
"""


class ExecutorSpinner:
    """rclpy's executor, one turn per message (the baseline the plain path improves on)."""

    def __init__(self, node, check):
        from rclpy.executors import SingleThreadedExecutor
        self.executor = SingleThreadedExecutor(context=node.context)
        self.executor.add_node(node)

    def spin_once(self, timeout_s):
        self.executor.spin_once(timeout_sec=timeout_s)


def _message_loop(kind, n, env):
    """CPU microseconds per message of this thread taking ``n`` messages through ``kind``."""
    import rclpy
    from std_msgs.msg import String

    from motoflex_ros.nodes import transport
    from motoflex_ros.nodes.qos_profiles import reliable_qos
    context = rclpy.Context()
    rclpy.init(context=context, domain_id=int(env["ROS_DOMAIN_ID"]))
    try:
        node = rclpy.create_node("bench_listener", context=context)
        got = []
        topic = f"bench_probe_{kind}_{time.monotonic_ns()}"   # no stale reader of a last loop
        node.create_subscription(String, topic, got.append, reliable_qos(), raw=True)
        spinners = {"executor": ExecutorSpinner, **{k: m.Spinner
                                                    for k, m in transport.TRANSPORTS.items()}}
        spinner = spinners[kind](node, lambda sub, gid, seq: None)
        talker = subprocess.Popen([sys.executable, "-c", PUBLISHER, str(n), topic], env=env)
        while not got:
            spinner.spin_once(0.1)
        cpu = time.thread_time()
        while len(got) < n:
            spinner.spin_once(0.1)
        cpu = time.thread_time() - cpu
        assert talker.wait(120) == 0
        node.destroy_node()
    finally:
        rclpy.try_shutdown(context=context)
    return cpu / (n - 1) * 1e6


def _campaign(kind, tmp):
    """(graph wall time [s], CPU seconds of the process tree) of one swingarm campaign."""
    out = Path(tmp) / f"run_{kind}_{time.monotonic_ns()}"
    env = dict(os.environ, MOTOFLEX_TRANSPORT=kind, OPENBLAS_NUM_THREADS="1", TMPDIR=tmp)
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    run = subprocess.run([sys.executable, "-m", "motoflex_ros.cli.main", "campaign",
                          "--component", "swingarm", "--report", "none", "--out", str(out)],
                         env=env, capture_output=True, text=True, timeout=900)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    assert run.returncode == 0, run.stderr[-2000:]
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return json.loads((out / "timings.json").read_text())["graph"], cpu


def _per_call_us(function, number=2000):
    import timeit
    return min(timeit.repeat(function, number=number, repeat=5)) / number * 1e6


def _cdr_and_quaternions():
    """Print microseconds per call: the hand-written paths against the library ones."""
    import numpy as np
    from geometry_msgs.msg import PoseArray, WrenchStamped
    from rclpy.serialization import deserialize_message, serialize_message
    from scipy.spatial.transform import Rotation

    from motoflex_ros.nodes import cdr, conversions
    from motoflex_ros.spatial import quaternion_xyzw
    points = np.random.default_rng(0).normal(size=(6, 3))
    ns = 1_234_567_890_123
    rotation = Rotation.from_rotvec([0.01, 0.02, 0.03]).as_matrix()
    rotations = np.stack([rotation] * 12)
    points_bytes, wrench_bytes = cdr.points_cdr(ns, "f", points), cdr.wrench_cdr(ns, "f", 3.0)
    cases = {
        "PoseArray of 6 markers, write": (
            lambda: cdr.points_cdr(ns, "f", points),
            lambda: serialize_message(conversions.points_msg(ns, "f", points))),
        "PoseArray of 6 markers, read": (
            lambda: cdr.points_from_cdr(points_bytes),
            lambda: conversions.points_from_msg(deserialize_message(points_bytes, PoseArray))),
        "WrenchStamped, write": (
            lambda: cdr.wrench_cdr(ns, "f", 3.0),
            lambda: serialize_message(conversions.wrench_msg(ns, "f", 3.0))),
        "WrenchStamped, read": (
            lambda: cdr.wrench_vector_from_cdr(wrench_bytes),
            lambda: deserialize_message(wrench_bytes, WrenchStamped)),
        "PoseStamped, write": (
            lambda: cdr.pose_cdr(ns, "f", points[0], rotation),
            lambda: serialize_message(conversions.pose_msg(ns, "f", points[0], rotation))),
        "quaternion of one matrix": (
            lambda: quaternion_xyzw(rotation),
            lambda: Rotation.from_matrix(rotation).as_quat()),
        "quaternions of 12 matrices": (
            lambda: [quaternion_xyzw(r) for r in rotations],
            lambda: Rotation.from_matrix(rotations).as_quat()),
    }
    print("hand-written against library, microseconds per call (library: rclpy message "
          "objects and serialize_message, scipy Rotation):")
    for what, (ours, library) in cases.items():
        a, b = _per_call_us(ours), _per_call_us(library)
        print(f"  {what:32s} ours {a:7.1f} us   library {b:7.1f} us   ratio {b / a:5.1f}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--messages", type=int, default=20_000)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--no-graph", action="store_true")
    parser.add_argument("--cdr", action="store_true")
    args = parser.parse_args()
    if args.cdr:
        _cdr_and_quaternions()
        return
    from motoflex_ros.launcher.domain import DomainLock
    from motoflex_ros.launcher.graph import ros_env
    kinds = ("ctypes", "rclpy", "executor")
    with tempfile.TemporaryDirectory() as tmp, DomainLock() as lock:
        env = ros_env(lock.domain_id, Path(tmp) / "log")
        per_message = {kind: [] for kind in kinds}
        for _ in range(args.repeat):
            for kind in kinds:
                per_message[kind].append(_message_loop(kind, args.messages, env))
    loop = {kind: statistics.median(v) for kind, v in per_message.items()}
    print(f"message loop, CPU per message taken ({args.messages} messages, median of "
          f"{args.repeat} alternated runs):")
    for kind, us in loop.items():
        print(f"  {kind:8s} {us:7.1f} us   ratio to ctypes {us / loop['ctypes']:5.2f}")
    if args.no_graph:
        return
    runs = {"ctypes": [], "rclpy": []}
    with tempfile.TemporaryDirectory() as tmp:
        for _ in range(args.repeat):
            for kind in runs:
                runs[kind].append(_campaign(kind, tmp))
    print(f"bench graph: swingarm campaign, median of {args.repeat} alternated runs:")
    wall = {k: statistics.median(r[0] for r in v) for k, v in runs.items()}
    cpu = {k: statistics.median(r[1] for r in v) for k, v in runs.items()}
    for kind in runs:
        print(f"  {kind:8s} graph {wall[kind]:6.1f} s wall, {cpu[kind]:6.1f} s CPU (all "
              f"processes)")
    print(f"  ratio plain/ctypes: wall {wall['rclpy'] / wall['ctypes']:.2f}, "
          f"CPU {cpu['rclpy'] / cpu['ctypes']:.2f}")


if __name__ == "__main__":
    main()
