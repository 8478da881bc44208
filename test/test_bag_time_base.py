"""The campaign bag's time base and moving frames, read with rosbags alone (issue 24, point 7).

bags/example (a full campaign: frame, front_assembly, swingarm on the bench, then the road
test) is read with the rosbags library only, none of the project's readers, and held to:

- one clock: every stamped message (a Header or a Time first: the bench's loads, markers and
  poses, /clock, /tf, the road test) is logged at its own stamp, and the messages without one
  (the phase JSON, the identified values, the mode series) inside the run;
- the phases in sequence on that clock, in the campaign's order: each component's bench data
  starts after the previous component's ends (none restarts at 0), the road test after the
  bench, its 4 s of response spread over 4 s of stamps (not a burst);
- /clock from at or before the first message to at or after the last, never going back, and
  ticking inside every phase (it jumps: it is the earliest sample in flight, up to the load
  actuator's window ahead);
- each bench's loaded end moving on /tf: <c>_clamp -> <c>_loaded_end changes over the tests,
  and carried with the static marker frames of /tf_static it puts every marker where the
  component simulator's /bench/<c>/markers/true has it at the same stamp (to 1e-12 m), so the
  frames move by exactly the simulated displacement.

A bag logged at wall-clock receive times (the recorder before this change) fails the first
check: :func:`test_a_bag_logged_at_receive_time_fails_the_check`.
"""
import functools
import struct
from collections import defaultdict
from pathlib import Path

import numpy as np
import pytest

rosbags = pytest.importorskip("rosbags")
from rosbags.highlevel import AnyReader  # noqa: E402
from rosbags.typesys import Stores, get_typestore  # noqa: E402
from scipy.spatial.transform import Rotation  # noqa: E402

EXAMPLE = Path(__file__).resolve().parents[1] / "bags" / "example"
COMPONENTS = ("frame", "front_assembly", "swingarm")     # the campaign's order
PAUSE_NS = 100_000_000       # between two bench tests, and before the road test [ns]
STORE = get_typestore(Stores.ROS2_JAZZY)


def _ns(time):
    return time.sec * 1_000_000_000 + time.nanosec


@functools.cache
def _starts_with_stamp(type_name):
    """Is the first field of ``type_name`` a std_msgs/Header or a builtin_interfaces/Time?"""
    kind, detail = STORE.fielddefs[type_name][1][0][1]
    return detail in ("std_msgs/msg/Header", "builtin_interfaces/msg/Time")


class Message:
    """One message of a bag: topic, log time [ns], type, CDR bytes; decoded by rosbags when
    asked (decoding all 97,000 messages takes 10 s: only the stamps are read from every one,
    the first 12 bytes of a Header or Time after the CDR encapsulation)."""

    def __init__(self, topic, log_ns, msgtype, raw):
        self.topic, self.log_ns, self.msgtype, self.raw = topic, log_ns, msgtype, raw
        self._msg = self._stamps = None

    @property
    def msg(self):
        if self._msg is None:
            self._msg = STORE.deserialize_cdr(self.raw, self.msgtype)
        return self._msg

    @property
    def stamps(self):
        """The stamps [ns] the message carries first (Header, Time, a TFMessage's transforms)."""
        if self._stamps is None:
            self._stamps = self._read_stamps()
        return self._stamps

    def _read_stamps(self):
        if self.msgtype == "tf2_msgs/msg/TFMessage":
            return [_ns(t.header.stamp) for t in self.msg.transforms]
        if not _starts_with_stamp(self.msgtype):
            return []
        sec, nanosec = struct.unpack_from("<iI" if self.raw[1] == 1 else ">iI", self.raw, 4)
        return [sec * 1_000_000_000 + nanosec]


def read_bag(path):
    """[Message] of a bag, in log-time order, read by rosbags alone."""
    out = []
    with AnyReader([Path(path)]) as reader:
        for connection, log_ns, raw in reader.messages():
            out.append(Message(connection.topic, log_ns, connection.msgtype, bytes(raw)))
    out.sort(key=lambda m: m.log_ns)
    return out


@pytest.fixture(scope="module")
def messages():
    return read_bag(EXAMPLE)


def check_one_clock(messages):
    """Stamped messages logged at their stamps, the others inside the run; (first, last) log
    time [ns]."""
    stamped = [(m.topic, m.log_ns, s) for m in messages for s in m.stamps]
    wrong = [(t, log, s) for t, log, s in stamped if s != log]
    assert not wrong, f"{len(wrong)} messages logged off their stamps, e.g. {wrong[:3]}"
    first, last = min(s for _, _, s in stamped), max(s for _, _, s in stamped)
    outside = [(m.topic, m.log_ns) for m in messages if not first <= m.log_ns <= last]
    assert not outside, f"messages logged outside the run's stamps: {outside[:3]}"
    return first, last


def test_every_message_on_one_simulated_clock(messages):
    first, last = check_one_clock(messages)
    assert first == 0     # simulated time from 0 (ROS sim time), not the wall-clock epoch
    clock = [m.stamps[0] for m in messages if m.topic == "/clock"]
    assert clock[0] <= first and clock[-1] >= last, "/clock does not cover the messages"
    assert all(np.diff(clock) >= 0), "/clock goes back"
    for phase in ("/bench/frame/", "/bench/front_assembly/", "/bench/swingarm/", "/vehicle/"):
        stamps = [s for m in messages if m.topic.startswith(phase) for s in m.stamps]
        lo, hi = min(stamps), max(stamps)
        ticks = [c for c in clock if lo <= c <= hi]
        assert len(ticks) > 10, f"/clock skips {phase}"


def test_bench_phases_and_road_test_in_sequence(messages):
    spans = {}
    for c in COMPONENTS:
        stamps = [s for m in messages if m.topic.startswith(f"/bench/{c}/") for s in m.stamps]
        assert stamps == sorted(stamps), f"{c}: stamps go back (a restart)"
        spans[c] = (stamps[0], stamps[-1])
        phase = [m.log_ns for m in messages if m.topic == f"/bench/{c}/phase"]
        assert spans[c][0] - PAUSE_NS <= min(phase) and max(phase) <= spans[c][1] + PAUSE_NS
    for a, b in zip(COMPONENTS, COMPONENTS[1:]):
        assert spans[a][1] < spans[b][0] <= spans[a][1] + 2 * PAUSE_NS, (a, b, spans)
    assert spans[COMPONENTS[0]][0] == 0 and spans[COMPONENTS[-1]][1] > 30e9
    road = [m.stamps[0] for m in messages if m.topic == "/vehicle/joint_states"]
    assert road[0] > spans[COMPONENTS[-1]][1]
    assert (road[-1] - road[0]) / 1e9 == pytest.approx(4.0, abs=0.01)    # the 4 s response
    assert len(road) == 801 and np.ptp(np.diff(road)) <= 1                 # every 5 ms


def _transform(t):
    q, p = t.transform.rotation, t.transform.translation
    return Rotation.from_quat([q.x, q.y, q.z, q.w]).as_matrix(), np.array([p.x, p.y, p.z])


def test_each_loaded_end_moves_with_the_simulated_markers(messages):
    offsets = defaultdict(dict)
    for m in messages:
        if m.topic == "/tf_static":
            for tf in m.msg.transforms:
                if "_marker_" in tf.child_frame_id:
                    component, index = tf.child_frame_id.rsplit("_marker_", 1)
                    assert tf.header.frame_id == f"{component}_loaded_end"
                    offsets[component][int(index)] = _transform(tf)[1]
    true = {(m.topic, m.stamps[0]): m for m in messages if m.topic.endswith("/markers/true")}
    for c in COMPONENTS:
        moving = [tf for m in messages if m.topic == "/tf" for tf in m.msg.transforms
                  if tf.child_frame_id == f"{c}_loaded_end"]
        assert len(moving) > 100 and {tf.header.frame_id for tf in moving} == {f"{c}_clamp"}
        marker_offsets = np.array([offsets[c][i] for i in sorted(offsets[c])])
        travel = []
        for tf in moving:
            rotation, position = _transform(tf)
            markers = true[f"/bench/{c}/markers/true", _ns(tf.header.stamp)].msg.poses
            expected = np.array([[p.position.x, p.position.y, p.position.z] for p in markers])
            np.testing.assert_allclose(position + marker_offsets @ rotation.T, expected,
                                       atol=1e-12)
            travel.append(position)
        travel = np.ptp(np.array(travel), axis=0)
        # the static tests move the loaded end by tenths of a millimetre to millimetres
        assert 1e-5 < np.linalg.norm(travel) < 0.05, (c, travel)


def test_a_bag_logged_at_receive_time_fails_the_check(tmp_path):
    from rosbags.rosbag2 import StoragePlugin, Writer
    store = STORE
    clock_type = store.types["rosgraph_msgs/msg/Clock"]
    time_type = store.types["builtin_interfaces/msg/Time"]
    with Writer(tmp_path / "bag", version=9, storage_plugin=StoragePlugin.MCAP) as writer:
        connection = writer.add_connection("/clock", "rosgraph_msgs/msg/Clock", typestore=store)
        for k in range(3):    # stamps 0, 1, 2 s logged at a wall clock's 1.7e18 ns
            msg = clock_type(clock=time_type(sec=k, nanosec=0))
            writer.write(connection, 1_700_000_000_000_000_000 + k,
                         store.serialize_cdr(msg, "rosgraph_msgs/msg/Clock"))
    with pytest.raises(AssertionError, match="logged off their stamps"):
        check_one_clock(read_bag(tmp_path / "bag"))


LAYOUT = Path(__file__).resolve().parents[1] / "config" / "foxglove" / "campaign.json"


def _layout_paths(layout):
    """Every (panel, message path) the layout reads: 3D panels' topics, plots' series and
    x-axis paths."""
    for panel, config in layout["configById"].items():
        for topic in config.get("topics", {}):
            yield panel, topic
        for series in config.get("paths", []) + [config.get("xAxisPath") or {}]:
            if series:
                yield panel, series["value"]


def _field(store, type_name, path):
    """The type reached through ``path`` ('wrench.force.y', 'position[1]') of ``type_name``, or
    KeyError."""
    for part in [p for p in path.split(".") if p]:
        name = part.split("[")[0]
        fields = dict(store.fielddefs[type_name][1])
        kind, detail = fields[name]
        while kind.name in ("SEQUENCE", "ARRAY"):   # position[1]: the element's type
            kind, detail = detail[0]
        type_name = detail if kind.name == "NAME" else detail[0]
    return type_name


def test_foxglove_layout_reads_only_what_the_campaign_bag_has(messages):
    import json
    store = STORE
    layout = json.loads(LAYOUT.read_text())
    types = {m.topic: m.msgtype for m in messages}
    read = list(_layout_paths(layout))
    assert len(read) > 15
    for panel, path in read:
        topic, _, rest = path.partition(".")
        assert topic in types, f"{LAYOUT.name}: {panel} reads {topic}, not in the bag"
        _field(store, types[topic], rest)      # a field the message has (KeyError if not)
    # the 3D panels follow frames of the bag's tf tree
    frames = {tf.child_frame_id for m in messages if m.topic in ("/tf", "/tf_static")
              for tf in m.msg.transforms} | {"world"}
    for panel, config in layout["configById"].items():
        if "followTf" in config:
            assert config["followTf"] in frames, panel
    # the road-test plot's labels name the joints at the indices it plots
    names = next(m.msg.name for m in messages if m.topic == "/vehicle/joint_states")
    phase_names = next(m.msg.name for m in messages if m.topic.endswith("/phase_values"))
    for series in (s for c in layout["configById"].values() for s in c.get("paths", [])):
        if series["value"].startswith("/vehicle/joint_states.position["):
            index = int(series["value"].split("[")[1].rstrip("]"))
            assert names[index] == series["label"]
        if ".phase_values.position[" in series["value"]:
            index = int(series["value"].split("[")[1].rstrip("]"))
            assert series["label"].endswith(phase_names[index])
    # every panel of configById is placed in the layout tree
    placed, stack = set(), [layout["layout"]]
    while stack:
        node = stack.pop()
        if isinstance(node, str):
            placed.add(node)
        else:
            stack += [node["first"], node["second"]]
    assert placed == set(layout["configById"])
