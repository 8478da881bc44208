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
import struct
import zlib
from dataclasses import dataclass
from pathlib import Path

import yaml
from mcap.data_stream import ReadDataStream
from mcap.reader import make_reader
from mcap.records import Channel, Chunk, Message, Schema
from mcap.stream_reader import StreamReader, breakup_chunk
from mcap.writer import CompressionType, Writer

from motoflex_ros.errors import MotoflexError
from motoflex_ros.files import atomic_write_bytes, file_kind, open_output
from motoflex_ros.units import NS_PER_S

__all__ = ["BagError", "TopicInfo", "BagInfo", "BagMessage", "BagWriter", "message_definition",
           "type_hash", "bag_info", "read_messages", "repair", "find_mcap", "METADATA_FILE",
           "check_new_bag_dir", "qos_yaml", "RELIABLE_KEEP_ALL", "INFINITE_NS"]

METADATA_FILE = "metadata.yaml"
BAG_FORMAT_VERSION = 9
LIBRARY = "motoflex_ros.record.mcap_bag"
DEFAULT_CHUNK_SIZE = 256 * 1024
REPAIR_METADATA = "motoflex_repair"   # the MCAP metadata record of a repaired bag
FOOTER_TAIL = 1 + 8 + 8 + 8 + 4 + 8   # footer record (opcode, length, 3 fields) + magic
FOOTER_OPCODE = 0x02
MAGIC = b"\x89MCAP0\r\n"
# what reading a damaged MCAP file raises: McapError, and besides it whatever the parser and
# the decompressors meet in bad bytes (struct.error, ValueError, EOFError, KeyError,
# zstandard's ZstdError and lz4's errors, which are plain Exceptions). Caught only around the
# reading of file bytes, where any of them means "this file is damaged", and turned into a
# BagError naming the file and where in it.
MCAP_ERRORS = (Exception,)
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
                sec, nsec = divmod(int(value), NS_PER_S)
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
    repaired: str = ""
    """'' for a bag as recorded; for one written by :func:`repair`, what it salvaged."""

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


def _summary_crc_problem(stream):
    """Why the summary section's CRC (the footer's summary_crc) does not hold, or None."""
    size = stream.seek(0, io.SEEK_END)
    if size < FOOTER_TAIL:
        return None   # too short for a footer: the reader says what is wrong
    stream.seek(size - FOOTER_TAIL)
    _, _, summary_start, _, expected = struct.unpack("<BQQQI", stream.read(FOOTER_TAIL - 8))
    if not expected or not summary_start or summary_start >= size:
        return None
    stream.seek(summary_start)
    actual = zlib.crc32(stream.read(size - 8 - 4 - summary_start))
    if actual != expected:
        return (f"summary section at byte offset {summary_start} is corrupt (CRC "
                f"{actual:#010x}, the footer says {expected:#010x})")
    return None


def _open_summary(mcap_file):
    try:
        with open(mcap_file, "rb") as stream:
            problem = _summary_crc_problem(stream)
            stream.seek(0)
            reader = make_reader(stream)
            summary = None if problem else reader.get_summary()
            repaired = {} if problem or summary is None else {
                k: v for m in reader.iter_metadata() if m.name == REPAIR_METADATA
                for k, v in m.metadata.items()}
    except MCAP_ERRORS as exc:
        raise BagError(f"{mcap_file}: not a readable MCAP file ({_what(exc)}); if its "
                       f"recorder was killed, run 'motoflex bag repair "
                       f"{mcap_file.parent}'") from None
    if problem:
        raise BagError(f"{mcap_file}: {problem}; 'motoflex bag repair {mcap_file.parent}' "
                       f"writes a new bag of what can be salvaged")
    if summary is None or summary.statistics is None:
        raise BagError(f"{mcap_file}: MCAP file has no summary; run 'motoflex bag repair'")
    return summary, repaired


def _what(exc):
    """An exception of a corrupt file, in one short line."""
    text = " ".join(str(exc).split())[:160]
    return f"{type(exc).__name__}: {text}" if text else type(exc).__name__


def bag_info(path, verify=False):
    """Topics, counts and times of a bag, from its MCAP summary (see :class:`BagInfo`);
    ``verify``: read every chunk too and check its CRC and the message counts
    (BagError naming the first corrupt chunk and its byte offset)."""
    mcap_file = find_mcap(path)
    bag_dir = mcap_file.parent
    if not (bag_dir / METADATA_FILE).is_file():
        raise BagError(f"{bag_dir}: no {METADATA_FILE} (recorder killed?); run "
                       f"'motoflex bag repair {bag_dir}'")
    summary, repaired = _open_summary(mcap_file)
    if verify:
        for _ in read_messages(mcap_file):
            pass
    stats = summary.statistics
    counts = stats.channel_message_counts
    topics = tuple(TopicInfo(ch.topic, summary.schemas[ch.schema_id].name, counts.get(cid, 0),
                             ch.metadata.get("offered_qos_profiles", ""))
                   for cid, ch in sorted(summary.channels.items()))
    start = stats.message_start_time if stats.message_count else 0
    end = stats.message_end_time if stats.message_count else 0
    return BagInfo(bag_dir, mcap_file, topics, stats.message_count, start, end - start,
                   _repair_text(repaired))


def _repair_text(repaired):
    if not repaired:
        return ""
    return (f"salvaged {repaired.get('messages_salvaged', '?')} messages from "
            f"{repaired.get('source', '?')}: {repaired.get('lost', '?')}")


def _chunk_records(stream, mcap_file, index, number, total):
    """The records of one chunk, its CRC checked; BagError naming it if it is corrupt."""
    try:
        stream.seek(index.chunk_start_offset + 1 + 8)
        chunk = Chunk.read(ReadDataStream(stream))
        return breakup_chunk(chunk, validate_crc=True)
    except MCAP_ERRORS as exc:
        raise BagError(f"{mcap_file}: chunk {number} of {total} at byte offset "
                       f"{index.chunk_start_offset} is corrupt ({_what(exc)}); "
                       f"'motoflex bag repair {mcap_file.parent}' writes a new bag without "
                       f"it") from None


def read_messages(path, topics=None):
    """Yield the :class:`BagMessage` of a bag in file (recording) order, optionally filtered.

    Every chunk's CRC is checked as it is read, and at the end the number of messages read
    against the summary's: a corrupt or duplicated chunk is a BagError naming it, never a
    message silently lost or read twice."""
    mcap_file = find_mcap(path)
    summary, _ = _open_summary(mcap_file)
    wanted = None if topics is None else set(topics)
    channels = {cid for cid, ch in summary.channels.items() if wanted is None or
                ch.topic in wanted}
    expected = sum(summary.statistics.channel_message_counts.get(c, 0) for c in channels)
    if expected and not summary.chunk_indexes:
        raise BagError(f"{mcap_file}: MCAP file without chunk index (not written by a "
                       f"rosbag2 MCAP writer); 'motoflex bag repair' rewrites it")
    indexes = sorted(summary.chunk_indexes, key=lambda c: c.chunk_start_offset)
    read = 0
    with open(mcap_file, "rb") as stream:
        for number, index in enumerate(indexes, 1):
            if channels.isdisjoint(index.message_index_offsets):
                continue
            for record in _chunk_records(stream, mcap_file, index, number, len(indexes)):
                if isinstance(record, Message) and record.channel_id in channels:
                    channel = summary.channels[record.channel_id]
                    read += 1
                    yield BagMessage(channel.topic, summary.schemas[channel.schema_id].name,
                                     record.log_time, record.data)
    if read != expected:
        raise BagError(f"{mcap_file}: {read} messages in its chunks, its summary counts "
                       f"{expected} (a chunk lost or duplicated); 'motoflex bag repair' "
                       f"writes a new bag")


@dataclass
class Salvage:
    """What :func:`_salvage` kept of an MCAP file and what it lost, in words."""

    schemas: dict
    channels: dict
    messages: list
    lost_chunks: list
    end: str

    def lost(self):
        """What the salvage could not keep, in words."""
        parts = [f"chunk at byte offset {o} corrupt ({why})" for o, why in self.lost_chunks]
        return "; ".join(p for p in (*parts, self.end) if p) or "nothing"


def _salvage(mcap_file):
    """Schemas, channels and messages of an MCAP file: every chunk whose CRC holds, up to
    the last complete record (a corrupt chunk is skipped and noted)."""
    found = Salvage({}, {}, [], [], "")
    with open(mcap_file, "rb") as stream:
        reader = StreamReader(stream, emit_chunks=True)
        try:
            for record in reader.records:
                _keep(found, record, stream.tell() - _record_size(record))
        except MCAP_ERRORS as exc:  # a truncated or damaged stream ends the salvage
            if not (found.schemas or found.channels or found.messages):
                raise BagError(f"{mcap_file}: nothing to salvage ({_what(exc)})") from None
            found.end = f"the file ends in a damaged or incomplete record ({_what(exc)})"
    return found


def _record_size(record):
    """Bytes of a Chunk record in the file (opcode and length included; 0 for others)."""
    if not isinstance(record, Chunk):
        return 0
    return 1 + 8 + 8 + 8 + 8 + 4 + 4 + len(record.compression) + 8 + len(record.data)


def _keep(found, record, offset):
    """Keep ``record`` (a Chunk starting at byte ``offset``: its records, if its CRC holds)."""
    if isinstance(record, Chunk):
        try:
            records = breakup_chunk(record, validate_crc=True)
        except MCAP_ERRORS as exc:
            found.lost_chunks.append((offset, _what(exc)))
            return
        for inner in records:
            _keep(found, inner, offset)
    elif isinstance(record, Schema):
        found.schemas[record.id] = record
    elif isinstance(record, Channel):
        found.channels[record.id] = record
    elif isinstance(record, Message):
        found.messages.append(record)


def _finished(mcap_file):
    """Did the writer finish ``mcap_file`` (a footer record and the closing magic at its end),
    however damaged the rest may be?"""
    with open(mcap_file, "rb") as stream:
        size = stream.seek(0, io.SEEK_END)
        if size < FOOTER_TAIL + 8:
            return False
        stream.seek(size - FOOTER_TAIL)
        tail = stream.read(FOOTER_TAIL)
    return tail[0] == FOOTER_OPCODE and tail[-8:] == MAGIC


def repair(path, out=None, chunk_size=DEFAULT_CHUNK_SIZE):
    """Salvage a bag and write it as a valid bag, marked as repaired; returns its BagInfo.

    A bag whose writer was killed (no footer at the end) is rewritten in place (the job of
    ``ros2 bag reindex``: the file was never a complete bag). A finished bag is never touched: the
    salvage goes to ``out`` (default ``<bag>_repaired`` beside it), a new bag directory.
    Chunks whose CRC fails are left out. The new MCAP holds a metadata record
    ``motoflex_repair`` (source, messages kept, what was lost) that :func:`bag_info` reports
    as ``repaired``, so replay and report say so.
    """
    mcap_file = find_mcap(path)
    if _finished(mcap_file) or out is not None:
        target_dir = check_new_bag_dir(Path(out) if out is not None else
                                       mcap_file.parent.with_name(
                                           f"{mcap_file.parent.name}_repaired"))
        target = target_dir / f"{target_dir.name}_0.mcap"
    else:
        target_dir, target = mcap_file.parent, mcap_file
    found = _salvage(mcap_file)
    stream = io.BytesIO()
    mark = {"source": str(mcap_file), "messages_salvaged": str(len(found.messages)),
            "lost": found.lost(), "in_place": str(target == mcap_file).lower()}
    _rewrite(stream, found, chunk_size, mark)
    target_dir.mkdir(parents=True, exist_ok=True)
    atomic_write_bytes(target, stream.getvalue())
    counts = {}
    for message in found.messages:
        counts[message.channel_id] = counts.get(message.channel_id, 0) + 1
    topics = tuple(TopicInfo(ch.topic, found.schemas[ch.schema_id].name, counts.get(cid, 0),
                             ch.metadata.get("offered_qos_profiles", ""))
                   for cid, ch in sorted(found.channels.items()))
    times = [m.log_time for m in found.messages] or [0]
    write_metadata(target_dir, target, topics, min(times), max(times) - min(times))
    return bag_info(target_dir)


def _rewrite(stream, found, chunk_size, mark):
    schemas, channels, messages = found.schemas, found.channels, found.messages
    writer = Writer(stream, chunk_size=chunk_size, compression=CompressionType.ZSTD)
    writer.start(profile="ros2", library=LIBRARY)
    writer.add_metadata("rosbag2", {"ROS_DISTRO": "jazzy"})
    writer.add_metadata(REPAIR_METADATA, mark)
    schema_ids = {sid: writer.register_schema(s.name, s.encoding, s.data)
                  for sid, s in sorted(schemas.items())}
    channel_ids = {cid: writer.register_channel(c.topic, c.message_encoding,
                                                schema_ids[c.schema_id], c.metadata)
                   for cid, c in sorted(channels.items())}
    for m in messages:
        if m.channel_id in channel_ids:   # a message whose channel was in a lost chunk: gone
            writer.add_message(channel_ids[m.channel_id], m.log_time, m.data, m.publish_time,
                               m.sequence)
    writer.finish()
