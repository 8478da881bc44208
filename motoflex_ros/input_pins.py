"""A run pinned to its inputs: every input file read once by the launcher, its SHA-256 checked by
every node that reads it again, and once more when the run ends.

Every configuration and model file the package reads (components, protocols, vehicles, bench
files, superelement matrices, node parameter files) goes through :func:`read_input`. Outside a
run it only reads the file. Inside :func:`recording_inputs` it also notes {path: SHA-256 of the
bytes read}: the launcher learns a run's inputs by loading them once. The launcher writes that
map to a JSON file and names it in ``MOTOFLEX_INPUT_PINS`` for its nodes; a node whose read
gives other bytes than the pinned ones stops with :class:`InputChanged` naming the file, so no
run mixes two versions of one input (issue 23, point 2). :func:`check_pins` re-reads every
pinned file at the end: a file changed during the run fails it, even when every node had read
it before the change.
"""
import hashlib
import json
import os
from contextlib import contextmanager
from pathlib import Path

from motoflex_ros.errors import MotoflexError
from motoflex_ros.files import atomic_write_text

__all__ = ["InputChanged", "PINS_ENV", "read_input", "note_input", "recording_inputs",
           "sha256_bytes", "sha256_file", "check_pins", "load_pins", "write_pins"]

PINS_ENV = "MOTOFLEX_INPUT_PINS"
_recorders = []
_pins_cache = {}


class InputChanged(MotoflexError):
    """An input file of a run is not what the run started with."""


def sha256_bytes(data):
    """Hex SHA-256 of ``data``.

    >>> sha256_bytes(b"")[:16]
    'e3b0c44298fc1c14'
    """
    return hashlib.sha256(data).hexdigest()


def sha256_file(path, block=1 << 20):
    """Hex SHA-256 of the file ``path``, read in blocks (a bag of gigabytes too)."""
    digest = hashlib.sha256()
    with open(path, "rb") as stream:
        for data in iter(lambda: stream.read(block), b""):
            digest.update(data)
    return digest.hexdigest()


def _key(path):
    return str(Path(path).resolve())


def load_pins(env=None):
    """{absolute path: SHA-256} the launcher pinned for this process (``MOTOFLEX_INPUT_PINS``),
    or {} outside a run."""
    where = (os.environ if env is None else env).get(PINS_ENV)
    if not where:
        return {}
    if where not in _pins_cache:
        try:
            pins = json.loads(Path(where).read_text(encoding="utf-8"))
        except (OSError, ValueError) as exc:
            raise InputChanged(f"{where}: the run's input pins ({PINS_ENV}) cannot be read "
                               f"({exc})") from None
        if not isinstance(pins, dict):
            raise InputChanged(f"{where}: the run's input pins ({PINS_ENV}) are not a mapping")
        _pins_cache[where] = pins
    return _pins_cache[where]


def write_pins(path, pins):
    """Write the pins {absolute path: SHA-256} as JSON to ``path``; returns the path."""
    return atomic_write_text(path, json.dumps(pins, indent=1, sort_keys=True) + "\n")


def _checked(path, digest):
    """Note ``path``'s content hash ``digest`` with the recorders; InputChanged if it is not
    the pinned content's."""
    key = _key(path)
    pinned = load_pins().get(key)
    if pinned is not None and pinned != digest:
        raise InputChanged(f"{path}: input changed during the run (SHA-256 {digest[:16]}... "
                           f"now, {pinned[:16]}... when the run started); rerun with the "
                           f"file as you want it")
    for record in _recorders:
        record[key] = digest


def read_input(path):
    """The bytes of input file ``path``, checked against the run's pin (if any) and noted by
    every active :func:`recording_inputs`."""
    data = Path(path).read_bytes()
    _checked(path, sha256_bytes(data))
    return data


def note_input(path):
    """Check and note an input that another library reads itself (a mesh file): hashed here
    in blocks, never held in memory whole."""
    _checked(path, sha256_file(path))


@contextmanager
def recording_inputs():
    """Within: every :func:`read_input` adds {absolute path: SHA-256} to the yielded dict."""
    record = {}
    _recorders.append(record)
    try:
        yield record
    finally:
        _recorders.remove(record)


def check_pins(pins):
    """InputChanged naming the first pinned file that is gone or no longer has its hash."""
    for path, digest in sorted(pins.items()):
        try:
            now = sha256_file(path)
        except OSError as exc:
            raise InputChanged(f"{path}: input of the run is gone or unreadable at its end "
                               f"({exc.strerror or exc})") from None
        if now != digest:
            raise InputChanged(f"{path}: input changed during the run (SHA-256 {now[:16]}... "
                               f"now, {digest[:16]}... when it started); its results are not "
                               f"from one version of it")
