"""Conversions between the core's numbers (SI, numpy) and ROS 2 messages. Nothing else here.

Times: integer nanoseconds of simulated time <-> builtin_interfaces/Time.
"""
import struct

from builtin_interfaces.msg import Time
from rclpy.serialization import deserialize_message
from rosgraph_msgs.msg import Clock

__all__ = ["time_msg", "time_ns", "clock_msg", "seconds_to_ns", "clock_ns_from_cdr"]

NS_PER_S = 1_000_000_000


def seconds_to_ns(seconds):
    """Simulated time [s] -> integer nanoseconds, rounded to the nearest nanosecond."""
    return int(round(seconds * NS_PER_S))


def time_msg(ns):
    """builtin_interfaces/Time of ``ns`` nanoseconds (ns >= 0)."""
    sec, nanosec = divmod(int(ns), NS_PER_S)
    return Time(sec=sec, nanosec=nanosec)


def time_ns(stamp):
    """Integer nanoseconds of a builtin_interfaces/Time."""
    return stamp.sec * NS_PER_S + stamp.nanosec


def clock_msg(ns):
    """rosgraph_msgs/Clock at ``ns`` nanoseconds of simulated time."""
    return Clock(clock=time_msg(ns))


def clock_ns_from_cdr(data):
    """Simulated time [ns] of a serialized rosgraph_msgs/Clock (fast path: little-endian)."""
    if len(data) >= 12 and data[1] == 1:
        sec, nanosec = struct.unpack_from("<iI", data, 4)
        return sec * NS_PER_S + nanosec
    return time_ns(deserialize_message(data, Clock).clock)
