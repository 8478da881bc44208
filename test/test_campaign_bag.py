"""A recorded campaign bag as ROS, Foxglove and rviz users read it (issue 16, points 2-4).

One full campaign (the three components and the vehicle, ``--report none``) is recorded, on the
short bench protocol (test/data/short_bench.yaml: every test kind, a few hundred samples per
component; what is read here, the tf tree, the bodies, the QoS and the result topics, does not
depend on the protocol's lengths); the bag is then read with rosbags alone, no project code:
its tf tree (/tf, /tf_static as tf2_msgs/msg/TFMessage) links every frame id used in the bag to
one root, /vehicle/bodies holds one pose per body that the named tf frames reproduce, and the
poses follow the road test: the main frame body's roll is /vehicle/joint_states' roll and the
bodies above and below it move sideways by their height times the sine of the roll; each
topic's QoS in metadata.yaml is what its publisher offered (the latched ones transient local,
so a replay keeps them latched).
"""
import os
import subprocess
import sys
from collections import defaultdict

import numpy as np
import pytest
import yaml
from scipy.spatial.transform import Rotation
from test_campaign_graph import SHORT_PROTOCOL


@pytest.fixture(scope="module")
def bag(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("campaign")
    out = tmp / "run"
    env = dict(os.environ, TMPDIR=str(tmp), OPENBLAS_NUM_THREADS="1")
    run = subprocess.run([sys.executable, "-m", "motoflex_ros.cli.main", "campaign", "--out",
                          str(out), "--report", "none", "--protocol", SHORT_PROTOCOL],
                         env=env, capture_output=True, text=True, timeout=900)
    assert run.returncode == 0, run.stderr
    return out


@pytest.fixture(scope="module")
def messages(bag):
    """{topic: [message, ...]} of the bag, decoded by rosbags."""
    from rosbags.rosbag2 import Reader
    from rosbags.typesys import Stores, get_typestore
    store = get_typestore(Stores.ROS2_JAZZY)
    out = defaultdict(list)
    with Reader(bag) as reader:
        for connection, _, raw in reader.messages():
            out[connection.topic].append(store.deserialize_cdr(raw, connection.msgtype))
    return out


def _stamp(msg):
    return msg.header.stamp.sec * 10**9 + msg.header.stamp.nanosec


def _frames_used(messages):
    """Every non-empty frame id of the bag: headers, markers inside arrays, tf frames."""
    used = set()
    for msgs in messages.values():
        for msg in msgs:
            for item in (msg, *getattr(msg, "markers", ()), *getattr(msg, "transforms", ())):
                header = getattr(item, "header", None)
                used |= {header.frame_id} if header is not None else set()
                used |= {getattr(item, "child_frame_id", "")}
    return used - {""}


def _matrix(transform):
    q, p = transform.rotation, transform.translation
    out = np.eye(4)
    out[:3, :3] = Rotation.from_quat([q.x, q.y, q.z, q.w]).as_matrix()
    out[:3, 3] = p.x, p.y, p.z
    return out


def test_tf_tree_links_every_frame_of_the_bag_to_one_root(messages):
    parents = {}
    for topic in ("/tf_static", "/tf"):
        assert messages[topic], f"no {topic} in the bag"
        for msg in messages[topic]:
            for t in msg.transforms:
                assert parents.setdefault(t.child_frame_id, t.header.frame_id) == \
                    t.header.frame_id, f"{t.child_frame_id} has two parents"
    used = _frames_used(messages)
    assert {"odom", "vehicle", "frame_clamp", "front_assembly_clamp", "swingarm_clamp"} <= used
    roots = set()
    for frame in used:
        seen = [frame]
        while seen[-1] in parents:
            seen.append(parents[seen[-1]])
            assert len(seen) < 50, f"a loop in the tf tree: {seen}"
        roots.add(seen[-1])
    assert roots == {"world"}
    # the bench: clamp -> loaded end -> the sensor's markers, and the beam model as markers
    for c in ("frame", "front_assembly", "swingarm"):
        assert parents[f"{c}_loaded_end"] == f"{c}_clamp"
        assert sum(p == f"{c}_loaded_end" for p in parents.values()) >= 3
        (structure,) = messages[f"/bench/{c}/structure"]
        kinds = {m.type: m for m in structure.markers}
        members, nodes = kinds[5], kinds[7]   # LINE_LIST, SPHERE_LIST
        ends = {(p.x, p.y, p.z) for p in members.points}
        assert len(members.points) % 2 == 0 and len(members.points) > len(nodes.points)
        assert ends <= {(p.x, p.y, p.z) for p in nodes.points}   # members join nodes
        assert {m.header.frame_id for m in structure.markers} == {f"{c}_clamp"}


def test_bodies_are_distinct_named_and_follow_the_road_test(messages):
    transforms = defaultdict(dict)
    for msg in messages["/tf"]:
        for t in msg.transforms:
            transforms[_stamp(t)][t.child_frame_id] = t
    roll = {_stamp(m): dict(zip(m.name, m.position))["roll"]
            for m in messages["/vehicle/joint_states"]}
    bodies = messages["/vehicle/bodies"]
    assert len(bodies) > 100
    rows = []
    for msg in bodies:
        assert msg.header.frame_id == "odom"
        tf = transforms[_stamp(msg)]
        names = [n for n in tf if n.startswith("vehicle/")]
        assert len(names) == len(msg.poses) >= 5
        positions = np.array([[p.position.x, p.position.y, p.position.z] for p in msg.poses])
        # named frames: odom -> vehicle -> vehicle/<body> gives the PoseArray, pose by pose
        base = _matrix(tf["vehicle"].transform)
        assert tf["vehicle"].header.frame_id == "odom"
        named = np.array([(base @ _matrix(tf[n].transform))[:3, 3] for n in names])
        np.testing.assert_allclose(named, positions, atol=1e-9)
        gaps = np.linalg.norm(positions[:, None] - positions[None], axis=-1)
        assert gaps[~np.eye(len(positions), dtype=bool)].min() > 0.01   # one pose per body
        o = msg.poses[0].orientation    # the main frame body: R = R_z(psi) R_x(phi) R_y(theta)
        r = Rotation.from_quat([o.x, o.y, o.z, o.w]).as_matrix()
        rows.append((np.arcsin(r[2, 1]), np.arctan2(-r[0, 1], r[1, 1]), roll[_stamp(msg)],
                     positions))
    phi, psi, joint_roll = (np.array([row[k] for row in rows]) for k in range(3))
    positions = np.array([row[3] for row in rows])
    np.testing.assert_allclose(phi, joint_roll, atol=1e-9)
    assert np.abs(joint_roll).max() > 0.005          # the steer pulse rolls the bike
    # the path turns: every body moves sideways (the same path, within the roll's share)
    lateral = positions[:, :, 1] - positions[0, :, 1]
    assert np.abs(lateral).max(axis=0).min() > 0.3
    # and in the heading frame a body d_z above the frame's centre of mass moves by -d_z sin(phi)
    offsets = positions - positions[:, :1]
    side = -np.sin(psi)[:, None] * offsets[..., 0] + np.cos(psi)[:, None] * offsets[..., 1]
    for b in range(1, positions.shape[1]):
        if abs(offsets[0, b, 2]) > 0.15:
            expected = -offsets[:, b, 2] * np.sin(phi)
            assert np.corrcoef(side[:, b], expected)[0, 1] > 0.9, b


# what the nodes' code offers: reliable everywhere; transient local on the latched topics. DDS
# discovery carries reliability, durability, deadline, lifespan and liveliness, not history and
# depth (rosbag2 records those as 3 "unknown" and 0, and so does the recorder)
RELIABLE, TRANSIENT_LOCAL, VOLATILE, AUTOMATIC = 1, 1, 2, 1
INFINITE = {"sec": 9223372036, "nsec": 854775807}
COMPONENTS = ("frame", "front_assembly", "swingarm")
LATCHED = {"/vehicle/eigenvalues", "/vehicle/joint_axes", "/vehicle/geometry",
           "/identification/results",
           "/tf_static", *(f"/bench/{c}/structure" for c in COMPONENTS),
           *(f"/identification/{c}/{q}" for c in COMPONENTS for q in ("k", "l", "beta")),
           "/vehicle/modes/speed_kmh", *(f"/vehicle/modes/{m}/{q}" for m in
                                         ("weave", "wobble", "capsize")
                                         for q in ("frequency_hz", "real_part"))}


def test_each_topic_keeps_the_qos_its_publisher_offered(bag):
    from rosbags.rosbag2 import Reader
    meta = yaml.safe_load((bag / "metadata.yaml").read_text())["rosbag2_bagfile_information"]
    topics = {t["topic_metadata"]["name"]: t["topic_metadata"]
              for t in meta["topics_with_message_count"]}
    assert set(LATCHED) <= set(topics) and len(topics) > 20
    for name, topic in topics.items():
        profiles = yaml.safe_load(topic["offered_qos_profiles"])
        assert profiles, name
        for profile in profiles:
            assert profile["durability"] == (TRANSIENT_LOCAL if name in LATCHED
                                             else VOLATILE), (name, profile)
            assert (profile["reliability"], profile["liveliness"]) == (RELIABLE, AUTOMATIC)
            assert profile["deadline"] == profile["lifespan"] == INFINITE, (name, profile)
    with Reader(bag) as reader:   # rosbags reads the same profiles
        durability = {c.topic: {q.durability.value for q in c.ext.offered_qos_profiles}
                      for c in reader.connections}
    assert {t for t, d in durability.items() if d == {TRANSIENT_LOCAL}} == set(LATCHED)


def _series(messages, topic):
    (msg,) = messages[topic]
    assert len(msg.layout.dim) == 1 and msg.layout.dim[0].size == len(msg.data) > 0, topic
    return np.asarray(msg.data, float), msg.layout.dim[0].label


def test_results_as_numbers_a_plot_panel_draws(bag, messages):
    """Weave and wobble against speed and k, l, beta per component as Float64MultiArray,
    equal to the JSON forms (/vehicle/eigenvalues, identification.json) that other code
    reads."""
    import json
    speeds, label = _series(messages, "/vehicle/modes/speed_kmh")
    assert "km/h" in label
    (eig,) = messages["/vehicle/eigenvalues"]
    modes = {s.name.split("/")[1]: {kv.key: json.loads(kv.value) for kv in s.values}
             for s in eig.status}
    for mode in ("weave", "wobble"):
        np.testing.assert_array_equal(speeds, modes[mode]["speeds_kmh"])
        for quantity, key in (("frequency_hz", "frequency_hz"), ("real_part", "real")):
            values, label = _series(messages, f"/vehicle/modes/{mode}/{quantity}")
            expected = np.array([np.nan if v is None else v for v in modes[mode][key]])
            np.testing.assert_array_equal(values, expected)
            assert np.isfinite(values).sum() > len(values) // 2 and mode in label
    identified = json.loads((bag / "identification.json").read_text())
    for component, result in identified.items():
        for quantity, unit in (("k", "N m/rad"), ("l", "m"), ("beta", "rad")):
            values, label = _series(messages, f"/identification/{component}/{quantity}")
            assert f"[{unit}]" in label and "static, torsion, bending" in label
            np.testing.assert_array_equal(values, [result[m][quantity]
                                                   for m in ("static", "torsion", "bending")])
