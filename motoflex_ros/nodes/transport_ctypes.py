"""The rig's fast ROS transport: rcl and rmw through ctypes (the default; :mod:`.transport`).

rclpy 7.1 (Jazzy) hands a subscriber only the message and a dict of timestamps and sequence
numbers: the rmw message info's ``publisher_gid`` is dropped. Without it a subscriber cannot
tell who sent a message, nor count lost messages per publisher. So this path takes every
message itself with ``rcl_take_serialized_message`` on the subscription's rcl handle (the
pointer rclpy exposes), which fills the complete ``rmw_message_info_t``; a publisher's own GID
comes from ``rmw_get_gid_for_publisher``. :class:`Spinner` waits on every subscription of a node
at once and drains each ready one until it is empty: one wait per burst instead of one executor
turn per message (``benchmarks/bench_transport.py`` prints the ratio against the plain rclpy
path, :mod:`.transport_rclpy`).

The structures below are copied from rmw 7.3 (``rmw_message_info_t``, ``rmw_gid_t`` with
``RMW_GID_STORAGE_SIZE`` 16, :data:`.endpoints.GID_SIZE`) and rcutils 6.7
(``rcutils_uint8_array_t``, the allocator); the calls are those of rcl 9.2 and the handles
those of rclpy 7.1. :data:`CHECKED_VERSIONS` names
the releases this was checked against; :func:`check_versions` refuses any other major.minor
release (patch releases of a ROS distribution keep their ABI) with a message naming what it
found and how to run on the plain path. The first message taken also checks that its GID names
the rmw implementation, so a layout that differs all the same fails loudly instead of reading
garbage.
"""
import ctypes
import functools
import os
import re
from importlib import metadata
from pathlib import Path

from rclpy.impl.implementation_singleton import rclpy_implementation
from rclpy.serialization import deserialize_message

from motoflex_ros.errors import MotoflexError
from motoflex_ros.nodes.endpoints import GID_SIZE
from motoflex_ros.units import NS_PER_S

__all__ = ["Taker", "Spinner", "publisher_gid", "check_versions", "installed_versions",
           "CHECKED_VERSIONS"]

_TAKE_FAILED = 401   # RCL_RET_SUBSCRIPTION_TAKE_FAILED: nothing to take

# package: the release this module was checked against (its structures, calls and handles)
CHECKED_VERSIONS = {"rclpy": "7.1.5", "rcl": "9.2.8", "rmw": "7.3.2", "rcutils": "6.7.4"}
_DISTRIBUTIONS = {"rclpy": ("rclpy", "ros-rclpy"), "rcl": ("ros-rcl",), "rmw": ("ros-rmw",),
                  "rcutils": ("ros-rcutils",)}


def _version(package):
    """Installed version of a ROS package: its Python distribution (the PyPI wheels) or its
    ``package.xml`` on the ament index (a ROS installation), else None."""
    for name in _DISTRIBUTIONS[package]:
        try:
            return metadata.version(name)
        except metadata.PackageNotFoundError:
            pass
    for prefix in filter(None, os.environ.get("AMENT_PREFIX_PATH", "").split(os.pathsep)):
        xml = Path(prefix, "share", package, "package.xml")
        if xml.is_file():
            found = re.search(r"<version>\s*([^<\s]+)\s*</version>", xml.read_text())
            if found:
                return found.group(1)
    return None


@functools.cache
def installed_versions():
    """{package: installed version or None} of the packages in :data:`CHECKED_VERSIONS`."""
    return {package: _version(package) for package in CHECKED_VERSIONS}


def _major_minor(version):
    return tuple((version or "").split(".")[:2])


def check_versions(found=None):
    """Raise MotoflexError unless every package of :data:`CHECKED_VERSIONS` is installed in
    the major.minor release this module was checked against (``found``: {package: version},
    default :func:`installed_versions`)."""
    found = installed_versions() if found is None else found
    wrong = {p: v for p, v in found.items()
             if _major_minor(v) != _major_minor(CHECKED_VERSIONS[p])}
    if wrong:
        names = ", ".join(f"{p} {v or 'not found'}" for p, v in sorted(wrong.items()))
        checked = ", ".join(f"{p} {v}" for p, v in CHECKED_VERSIONS.items())
        raise MotoflexError(
            f"the ctypes ROS transport (nodes/transport_ctypes.py) was checked against {checked} "
            f"(the same major.minor releases accepted); this installation has {names}. Run on "
            f"the plain rclpy path instead: MOTOFLEX_TRANSPORT=rclpy")


class _Allocator(ctypes.Structure):
    _fields_ = [("allocate", ctypes.c_void_p), ("deallocate", ctypes.c_void_p),
                ("reallocate", ctypes.c_void_p), ("zero_allocate", ctypes.c_void_p),
                ("state", ctypes.c_void_p)]


class _Bytes(ctypes.Structure):   # rcutils_uint8_array_t = rmw_serialized_message_t
    _fields_ = [("buffer", ctypes.POINTER(ctypes.c_uint8)), ("buffer_length", ctypes.c_size_t),
                ("buffer_capacity", ctypes.c_size_t), ("allocator", _Allocator)]


class _Gid(ctypes.Structure):
    _fields_ = [("implementation_identifier", ctypes.c_char_p),
                ("data", ctypes.c_uint8 * GID_SIZE)]


class _MessageInfo(ctypes.Structure):
    _fields_ = [("source_timestamp", ctypes.c_int64), ("received_timestamp", ctypes.c_int64),
                ("publication_sequence_number", ctypes.c_uint64),
                ("reception_sequence_number", ctypes.c_uint64),
                ("publisher_gid", _Gid), ("from_intra_process", ctypes.c_bool)]


class _Libraries:
    """librcl, librcutils and the rmw implementation as rclpy loaded them (same copies)."""

    def __init__(self):
        loaded = _loaded_libraries()
        self.rcl = _library(loaded, "librcl.so")
        self.rcutils = _library(loaded, "librcutils.so")
        self.rmw = next((lib for lib in (_library(loaded, n) for n in loaded
                                         if n.startswith("librmw"))
                         if hasattr(lib, "rmw_get_gid_for_publisher")), None)
        if self.rmw is None:
            raise MotoflexError("no loaded rmw library provides rmw_get_gid_for_publisher")
        self.rcutils.rcutils_get_default_allocator.restype = _Allocator
        self.rcutils.rcutils_uint8_array_init.argtypes = [
            ctypes.POINTER(_Bytes), ctypes.c_size_t, ctypes.POINTER(_Allocator)]
        self.rcutils.rcutils_get_error_string.restype = ctypes.c_char * 1024
        self.rcl.rcl_take_serialized_message.argtypes = [
            ctypes.c_void_p, ctypes.POINTER(_Bytes), ctypes.POINTER(_MessageInfo),
            ctypes.c_void_p]
        self.rcl.rcl_publisher_get_rmw_handle.argtypes = [ctypes.c_void_p]
        self.rcl.rcl_publisher_get_rmw_handle.restype = ctypes.c_void_p
        self.rmw.rmw_get_gid_for_publisher.argtypes = [ctypes.c_void_p, ctypes.POINTER(_Gid)]

    def error(self, what, code):
        text = self.rcutils.rcutils_get_error_string().value.decode(errors="replace")
        self.rcutils.rcutils_reset_error()
        return MotoflexError(f"{what} failed (rcl return code {code}): {text}")


def _loaded_libraries():
    """{file name: path} of the shared libraries mapped into this process (rclpy's
    implementation, imported above, loaded rcl and the rmw implementation)."""
    with open("/proc/self/maps") as maps:
        paths = {line.split()[-1] for line in maps if ".so" in line}
    return {os.path.basename(p): p for p in sorted(paths) if p.startswith("/")}


def _library(loaded, name):
    return ctypes.CDLL(loaded.get(name, name))


_LIBS = []


def _libs():
    if not _LIBS:
        check_versions()
        _LIBS.append(_Libraries())
    return _LIBS[0]


def publisher_gid(publisher, node=None, known=()):
    """GID (bytes) of an rclpy publisher (asked of rmw; ``node`` and ``known``, which the plain
    path needs, are not)."""
    libs = _libs()
    gid = _Gid()
    with publisher.handle:
        rmw_handle = libs.rcl.rcl_publisher_get_rmw_handle(publisher.handle.pointer)
        code = libs.rmw.rmw_get_gid_for_publisher(rmw_handle, ctypes.byref(gid))
    if code != 0:
        raise libs.error(f"{publisher.topic_name}: rmw_get_gid_for_publisher", code)
    return bytes(gid.data)


class Taker:
    """Takes the messages of one rclpy subscription: ``take()`` -> (CDR bytes, publisher GID,
    publication sequence number), or None when there is none."""

    def __init__(self, subscription):
        libs = self._libs = _libs()
        self.subscription = subscription
        self._bytes = _Bytes()
        self._info = _MessageInfo()
        allocator = libs.rcutils.rcutils_get_default_allocator()
        code = libs.rcutils.rcutils_uint8_array_init(ctypes.byref(self._bytes), 4096,
                                                     ctypes.byref(allocator))
        if code != 0:
            raise libs.error("rcutils_uint8_array_init", code)
        self._take = libs.rcl.rcl_take_serialized_message
        self._args = (subscription.handle.pointer, ctypes.byref(self._bytes),
                      ctypes.byref(self._info), None)
        self._checked_layout = False

    def take(self):
        """The next message or None."""
        code = self._take(*self._args)
        if code == _TAKE_FAILED:
            return None
        if code != 0:
            raise self._libs.error(f"{self.subscription.topic_name}: take", code)
        info = self._info
        if not self._checked_layout:
            if not (info.publisher_gid.implementation_identifier or b"").startswith(b"rmw_"):
                raise MotoflexError("rmw_message_info_t of this ROS installation is not the "
                                    "layout motoflex_ros knows (Jazzy, rmw 7.3); run with "
                                    "MOTOFLEX_TRANSPORT=rclpy")
            self._checked_layout = True
        data = ctypes.string_at(self._bytes.buffer, self._bytes.buffer_length)
        return data, bytes(info.publisher_gid.data), info.publication_sequence_number


class Spinner:
    """Wait on every subscription of a node, then drain each ready one completely (a wait
    with n subscriptions costs about 5 n us; trying the others too would cost as much again
    for the recorder's 22). ``check(sub, publisher GID, sequence number)`` sees each message
    before its callback does."""

    def __init__(self, node, check):
        _libs()   # the versions are checked before the first wait
        self.node = node
        self.check = check
        self._takers = {}

    def spin_once(self, timeout_s):
        """Handle every message available within ``timeout_s`` [s]; returns the count."""
        subs = list(self.node.subscriptions)
        context = self.node.context
        if timeout_s != 0:
            with context.handle:
                wait_set = rclpy_implementation.WaitSet(len(subs), 0, 0, 0, 0, 0,
                                                        context.handle)
                for sub in subs:
                    wait_set.add_subscription(sub.handle)
                wait_set.wait(int(timeout_s * NS_PER_S))
                ready = set(wait_set.get_ready_entities("subscription"))
            subs = [sub for sub in subs if sub.handle.pointer in ready]
        return sum(self._drain(sub) for sub in subs)

    def _drain(self, sub):
        count = 0
        taker = self._takers.get(sub) or self._takers.setdefault(sub, Taker(sub))
        msg_type, raw, callback, check = sub.msg_type, sub.raw, sub.callback, self.check
        while True:
            taken = taker.take()
            if taken is None:
                return count
            data, gid, seq = taken
            check(sub, gid, seq)   # before the message is used: a foreign one stops the run
            callback(data if raw else deserialize_message(data, msg_type))
            count += 1

