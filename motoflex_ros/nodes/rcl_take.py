"""Take a message together with the GID of the publisher that sent it (rcl through ctypes).

rclpy 7.1 (Jazzy) hands a subscriber only the message and a dict of timestamps and sequence
numbers: the rmw message info's ``publisher_gid`` is dropped. Without it a subscriber cannot
tell who sent a message, nor count lost messages per publisher. So the rig takes every message
itself with ``rcl_take_serialized_message`` on the subscription's rcl handle (the pointer rclpy
exposes), which fills the complete ``rmw_message_info_t``; a publisher's own GID comes from
``rmw_get_gid_for_publisher``. The structures below are those of rmw 7.3 (Jazzy:
``RMW_GID_STORAGE_SIZE`` 16); the first message taken checks that its GID names the rmw
implementation, so a different layout fails loudly instead of reading garbage.
"""
import ctypes
import os

from motoflex_ros.errors import MotoflexError

__all__ = ["Taker", "publisher_gid", "GID_SIZE", "gid_text"]

GID_SIZE = 16
_TAKE_FAILED = 401   # RCL_RET_SUBSCRIPTION_TAKE_FAILED: nothing to take


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
    """{file name: path} of the shared libraries mapped into this process."""
    import rclpy  # noqa: F401  (loads rcl and the rmw implementation)
    with open("/proc/self/maps") as maps:
        paths = {line.split()[-1] for line in maps if ".so" in line}
    return {os.path.basename(p): p for p in sorted(paths) if p.startswith("/")}


def _library(loaded, name):
    return ctypes.CDLL(loaded.get(name, name))


_LIBS = []


def _libs():
    if not _LIBS:
        _LIBS.append(_Libraries())
    return _LIBS[0]


def gid_text(gid):
    """A GID as the dotted hex ROS tools print."""
    return ".".join(f"{b:02x}" for b in gid)


def publisher_gid(publisher):
    """GID (bytes) of an rclpy publisher."""
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
                                    "layout motoflex_ros knows (Jazzy, rmw 7.3)")
            self._checked_layout = True
        data = ctypes.string_at(self._bytes.buffer, self._bytes.buffer_length)
        return data, bytes(info.publisher_gid.data), info.publication_sequence_number
