"""Simulated time as ROS stamps: integer nanoseconds <-> builtin_interfaces/Time, /clock."""
from builtin_interfaces.msg import Time
from rosgraph_msgs.msg import Clock

from motoflex_ros.units import NS_PER_S

__all__ = ["seconds_to_ns", "time_msg", "time_ns", "clock_msg"]


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
