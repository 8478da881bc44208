"""rosbag2-compatible MCAP bags: writer, reader and repair of a bag whose writer was killed.

A bag is a directory holding ``metadata.yaml`` (rosbag2 format, version 9, storage ``mcap``) and
one MCAP file (profile ``ros2``; schemas as ``ros2msg`` text; messages as CDR bytes, e.g. from
``rclpy.serialization.serialize_message`` or a raw subscription). This module imports no rclpy:
it only moves serialized bytes. The schema text and the RIHS01 type hash of the standard ROS 2
Jazzy types come from the rosbags type store.

Each topic carries the QoS profiles its publishers offered (channel metadata and
metadata.yaml, as rosbag2 writes them), so ``ros2 bag play`` offers them again: a latched
(transient-local) topic stays latched in a replay.

The MCAP file is written in place with mcap's public Writer (chunks of ``chunk_size``, so that a
killed writer leaves something :func:`repair` can salvage up to the last complete chunk; file
name ``<bag>_0.mcap`` as rosbag2 names it; per-topic sequence numbers); ``metadata.yaml`` is
written atomically on close. (rosbags' rosbag2 Writer writes the same format at about the same
speed, measured in benchmarks/bench_recorder.py, but with a fixed 1 MiB uncompressed chunk, a
file name without ``_0``, no sequence numbers and no type hash in the channels.)
"""
import functools
import io
from dataclasses import dataclass
from pathlib import Path

import yaml
from mcap.exceptions import McapError
from mcap.reader import make_reader
from mcap.records import Channel, Message, Schema
from mcap.stream_reader import StreamReader
from mcap.writer import CompressionType, Writer

from motoflex_ros.errors import MotoflexError
from motoflex_ros.files import atomic_write_bytes, file_kind, open_output

__all__ = ["BagError", "TopicInfo", "BagInfo", "BagMessage", "BagWriter", "message_definition",
           "type_hash", "bag_info", "read_messages", "repair", "find_mcap", "METADATA_FILE",
           "check_new_bag_dir", "qos_yaml", "RELIABLE_KEEP_ALL", "INFINITE_NS"]

METADATA_FILE = "metadata.yaml"
BAG_FORMAT_VERSION = 9
LIBRARY = "motoflex_ros.record.mcap_bag"
DEFAULT_CHUNK_SIZE = 256 * 1024
INFINITE_NS = 2**63 - 1   # rmw's infinite duration [ns] (deadline, lifespan, lease)
# rosbag2's enum values, which are rmw's: history 1 keep last, 2 keep all; reliability 1
# reliable, 2 best effort; durability 1 transient local, 2 volatile; liveliness 1 automatic
RELIABLE_KEEP_ALL = {"history": 2, "depth": 0, "reliability": 1, "durability": 2,
                     "deadline": INFINITE_NS, "lifespan": INFINITE_NS, "liveliness": 1,
                     "liveliness_lease_duration": INFINITE_NS,
                     "avoid_ros_namespace_conventions": False}


def qos_yaml(profiles):
    """rosbag2's ``offered_qos_profiles`` text of QoS profiles: dicts with the keys of
    RELIABLE_KEEP_ALL (enum values as integers, durations in [ns], split into sec and nsec)."""
    def entry(profile):
        out = {}
        for key, value in profile.items():
            if key in ("deadline", "lifespan", "liveliness_lease_duration"):
                sec, nsec = divmod(int(value), 1_000_000_000)
                value = {"sec": sec, "nsec": nsec}
            out[key] = value
        return out
    return yaml.safe_dump([entry(p) for p in profiles], sort_keys=False)


class BagError(MotoflexError):
    """A path is not a readable bag, or a bag cannot be written there."""


@dataclass(frozen=True)
class TopicInfo:
    """One topic of a bag: name, ROS type ('pkg/msg/Type'), number of messages and the QoS
    its publishers offered (rosbag2's ``offered_qos_profiles`` text)."""

    name: str
    type: str
    count: int
    qos: str = ""


@dataclass(frozen=True)
class BagInfo:
    """Summary of a bag: topics with counts, total count, first log time and duration [ns]."""

    path: Path
    mcap_file: Path
    topics: tuple
    message_count: int
    start_ns: int
    duration_ns: int

    def count(self, topic):
        """Number of messages on ``topic`` (0 if the bag does not hold it)."""
        return next((t.count for t in self.topics if t.name == topic), 0)


@dataclass(frozen=True)
class BagMessage:
    """One recorded message: topic, ROS type, log time [ns] and CDR bytes."""

    topic: str
    type: str
    log_time_ns: int
    data: bytes


@functools.cache
def _typestore():
    from rosbags.typesys import Stores, get_typestore
    return get_typestore(Stores.ROS2_JAZZY)


@functools.cache
def message_definition(type_name):
    """The rosbag2 ``ros2msg`` schema text of a standard ROS 2 Jazzy type ('pkg/msg/Type')."""
    try:
        return _typestore().generate_msgdef(type_name, ros_version=2)[0]
    except KeyError as exc:
        raise BagError(f"unknown message type '{type_name}' (standard ROS 2 Jazzy types "
                       "only)") from exc


@functools.cache
def type_hash(type_name):
    """The RIHS01 type description hash of a standard ROS 2 Jazzy type."""
    return _typestore().hash_rihs01(type_name)


def check_new_bag_dir(path):
    """``path`` (a Path) if it does not exist or is an empty directory, else BagError."""
    path = Path(path)
    if path.exists() and (not path.is_dir() or any(path.iterdir())):
        raise BagError(f"{path}: exists and is not an empty directory; choose another --out")
    return path


class BagWriter:
    """Write a rosbag2 MCAP bag directory from serialized (CDR) messages.

    Use as a context manager or call :meth:`close`. ``path`` must not exist or be an empty
    directory. ``chunk_size`` [bytes] bounds what a killed writer loses.
    """

    def __init__(self, path, chunk_size=DEFAULT_CHUNK_SIZE, compression="zstd"):
        self.path = check_new_bag_dir(path)
        self.path.mkdir(parents=True, exist_ok=True)
        self.mcap_file = self.path / f"{self.path.name}_0.mcap"
        self._stream = open_output(self.mcap_file)   # closed in close(); errors name the file
        kinds = {"zstd": CompressionType.ZSTD, "lz4": CompressionType.LZ4,
                 "none": CompressionType.NONE}
        self._writer = Writer(self._stream, chunk_size=chunk_size,
                              compression=kinds[compression])
        self._writer.start(profile="ros2", library=LIBRARY)
        self._writer.add_metadata("rosbag2", {"ROS_DISTRO": "jazzy"})
        self._channels = {}
        self._types = {}
        self._qos = {}
        self._counts = {}
        self._first = None
        self._last = None
        self.closed = False

    def add_topic(self, topic, type_name, qos_profiles=(RELIABLE_KEEP_ALL,)):
        """Register ``topic`` of ROS type ``type_name`` with the QoS profiles its publishers
        offer (dicts, :func:`qos_yaml`); returns the channel id."""
        if topic in self._channels:
            if self._types[topic] != type_name:
                raise BagError(f"topic {topic} already recorded as {self._types[topic]}, "
                               f"not {type_name}")
            return self._channels[topic]
        schema_id = self._writer.register_schema(
            name=type_name, encoding="ros2msg", data=message_definition(type_name).encode())
        qos = qos_yaml(qos_profiles)
        channel_id = self._writer.register_channel(
            topic=topic, message_encoding="cdr", schema_id=schema_id,
            metadata={"offered_qos_profiles": qos, "topic_type_hash": type_hash(type_name)})
        self._channels[topic] = channel_id
        self._types[topic] = type_name
        self._qos[topic] = qos
        self._counts[topic] = 0
        return channel_id

    def write(self, topic, log_time_ns, data):
        """Append one message (CDR ``bytes``) of a registered ``topic`` at ``log_time_ns``."""
        sequence = self._counts[topic]
        self._writer.add_message(self._channels[topic], log_time_ns, data, log_time_ns,
                                 sequence)
        self._counts[topic] = sequence + 1
        if self._first is None or log_time_ns < self._first:
            self._first = log_time_ns
        if self._last is None or log_time_ns > self._last:
            self._last = log_time_ns

    @property
    def message_count(self):
        """Messages written so far."""
        return sum(self._counts.values())

    def close(self):
        """Finish the MCAP file (summary and footer) and write ``metadata.yaml`` atomically."""
        if self.closed:
            return
        self.closed = True
        try:
            self._writer.finish()
        finally:
            self._stream.close()   # also when the finish failed (a full disk): no open file
        topics = tuple(TopicInfo(t, self._types[t], self._counts[t], self._qos[t])
                       for t in self._channels)
        start = self._first or 0
        write_metadata(self.path, self.mcap_file, topics, start, (self._last or 0) - start)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


def _metadata_dict(mcap_file, topics, start_ns, duration_ns):
    per_topic = [{"topic_metadata": {"name": t.name, "type": t.type,
                                     "serialization_format": "cdr",
                                     "offered_qos_profiles": t.qos or qos_yaml(
                                         [RELIABLE_KEEP_ALL]),
                                     "type_description_hash": type_hash(t.type)},
                  "message_count": t.count} for t in topics]
    total = sum(t.count for t in topics)
    return {"rosbag2_bagfile_information": {
        "version": BAG_FORMAT_VERSION, "storage_identifier": "mcap",
        "duration": {"nanoseconds": duration_ns},
        "starting_time": {"nanoseconds_since_epoch": start_ns},
        "message_count": total, "topics_with_message_count": per_topic,
        "compression_format": "", "compression_mode": "",
        "relative_file_paths": [mcap_file.name],
        "files": [{"path": mcap_file.name, "starting_time": {"nanoseconds_since_epoch": start_ns},
                   "duration": {"nanoseconds": duration_ns}, "message_count": total}],
        "custom_data": {}, "ros_distro": "jazzy"}}


def write_metadata(bag_dir, mcap_file, topics, start_ns, duration_ns):
    """Write ``metadata.yaml`` of a bag atomically (temp file + rename)."""
    text = yaml.safe_dump(_metadata_dict(Path(mcap_file), topics, start_ns, duration_ns),
                          sort_keys=False)
    atomic_write_bytes(Path(bag_dir) / METADATA_FILE, text.encode())


def find_mcap(path):
    """The MCAP file of a bag directory (or ``path`` itself if it is an .mcap file)."""
    path = Path(path)
    if path.suffix == ".mcap" and path.exists() and not path.is_dir():
        return _regular(path)
    if not path.is_dir():
        raise BagError(f"{path}: not a bag (no such directory or .mcap file)")
    files = sorted(p for p in path.glob("*.mcap") if not p.name.startswith("."))
    if len(files) != 1:
        raise BagError(f"{path}: not a bag (expected one .mcap file, found {len(files)})")
    return _regular(files[0])


def _regular(path):
    """``path`` if it is a regular file (a FIFO, device or socket would block or never end
    when read: refused before it is opened), else BagError."""
    kind = file_kind(path.stat().st_mode)
    if kind:
        raise BagError(f"{path}: is {kind}, not a regular file: not a bag's MCAP file")
    return path


def _open_summary(mcap_file):
    try:
        with open(mcap_file, "rb") as stream:
            summary = make_reader(stream).get_summary()
    except (McapError, ValueError, OSError, EOFError, AssertionError) as exc:
        raise BagError(f"{mcap_file}: not a readable MCAP file ({exc}); if its recorder was "
                       f"killed, run 'motoflex bag repair {mcap_file.parent}'") from exc
    if summary is None or summary.statistics is None:
        raise BagError(f"{mcap_file}: MCAP file has no summary; run 'motoflex bag repair'")
    return summary


def bag_info(path):
    """Topics, counts and times of a bag, from its MCAP summary (see :class:`BagInfo`)."""
    mcap_file = find_mcap(path)
    bag_dir = mcap_file.parent
    if not (bag_dir / METADATA_FILE).is_file():
        raise BagError(f"{bag_dir}: no {METADATA_FILE} (recorder killed?); run "
                       f"'motoflex bag repair {bag_dir}'")
    summary = _open_summary(mcap_file)
    stats = summary.statistics
    counts = stats.channel_message_counts
    topics = tuple(TopicInfo(ch.topic, summary.schemas[ch.schema_id].name, counts.get(cid, 0),
                             ch.metadata.get("offered_qos_profiles", ""))
                   for cid, ch in sorted(summary.channels.items()))
    start = stats.message_start_time if stats.message_count else 0
    end = stats.message_end_time if stats.message_count else 0
    return BagInfo(bag_dir, mcap_file, topics, stats.message_count, start, end - start)


def read_messages(path, topics=None):
    """Yield the :class:`BagMessage` of a bag in file (recording) order, optionally filtered."""
    mcap_file = find_mcap(path)
    _open_summary(mcap_file)
    wanted = None if topics is None else set(topics)
    with open(mcap_file, "rb") as stream:
        reader = make_reader(stream)
        for schema, channel, message in reader.iter_messages(log_time_order=False):
            if wanted is None or channel.topic in wanted:
                yield BagMessage(channel.topic, schema.name, message.log_time, message.data)


def _salvage(mcap_file):
    """Schemas, channels and messages of an MCAP file up to its last complete record."""
    schemas, channels, messages = {}, {}, []
    with open(mcap_file, "rb") as stream:
        try:
            for record in StreamReader(stream).records:
                if isinstance(record, Schema):
                    schemas[record.id] = record
                elif isinstance(record, Channel):
                    channels[record.id] = record
                elif isinstance(record, Message):
                    messages.append(record)
        except Exception as exc:  # any truncation error ends the salvage
            if not schemas and not channels and not messages:
                raise BagError(f"{mcap_file}: nothing to salvage ({exc})") from exc
    return schemas, channels, messages


def repair(path, chunk_size=DEFAULT_CHUNK_SIZE):
    """Salvage a bag whose writer was killed and rewrite it as a valid bag; returns BagInfo.

    Reads the MCAP with a stream reader up to the last complete chunk, writes a new MCAP next to
    it (temporary name, then rename over the old file) and writes ``metadata.yaml`` with the
    true counts (the job of ``ros2 bag reindex``). A bag that is already valid is rewritten to
    the same content.
    """
    mcap_file = find_mcap(path)
    schemas, channels, messages = _salvage(mcap_file)
    stream = io.BytesIO()
    _rewrite(stream, schemas, channels, messages, chunk_size)
    atomic_write_bytes(mcap_file, stream.getvalue())
    counts = {}
    for message in messages:
        counts[message.channel_id] = counts.get(message.channel_id, 0) + 1
    topics = tuple(TopicInfo(ch.topic, schemas[ch.schema_id].name, counts.get(cid, 0),
                             ch.metadata.get("offered_qos_profiles", ""))
                   for cid, ch in sorted(channels.items()))
    times = [m.log_time for m in messages] or [0]
    write_metadata(mcap_file.parent, mcap_file, topics, min(times), max(times) - min(times))
    return bag_info(mcap_file.parent)


def _rewrite(stream, schemas, channels, messages, chunk_size):
    writer = Writer(stream, chunk_size=chunk_size, compression=CompressionType.ZSTD)
    writer.start(profile="ros2", library=LIBRARY)
    writer.add_metadata("rosbag2", {"ROS_DISTRO": "jazzy"})
    schema_ids = {sid: writer.register_schema(s.name, s.encoding, s.data)
                  for sid, s in sorted(schemas.items())}
    channel_ids = {cid: writer.register_channel(c.topic, c.message_encoding,
                                                schema_ids[c.schema_id], c.metadata)
                   for cid, c in sorted(channels.items())}
    for m in messages:
        writer.add_message(channel_ids[m.channel_id], m.log_time, m.data, m.publish_time,
                           m.sequence)
    writer.finish()
