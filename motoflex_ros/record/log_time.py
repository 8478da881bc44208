"""Log times of a bag on the run's one simulated clock (no rclpy here).

A campaign's nodes stamp every message with simulated time (the bench tests one after the
other, then the road test: docs/virtual-bench.md, "Time base"); a wall-clock receive time, as
``ros2 bag record`` writes, would put the road test's 4 s into the half second the computer
took for it. So the recorder writes each message at the simulated instant it describes:

- a message whose first field is a std_msgs/Header or a builtin_interfaces/Time (stamped
  messages, rosgraph_msgs/Clock) at that stamp;
- any other message (std_msgs/String, Float64MultiArray, MarkerArray ...) at the latest stamp
  recorded so far, or at the recorder's own clock (/clock under ``use_sim_time``) if that is
  later: the simulated time it was received at, to within the sample in flight.
"""
import functools
import struct

from motoflex_ros.units import NS_PER_S

__all__ = ["STAMP_TYPES", "is_stamped", "stamp_ns", "SimLogTime"]

STAMP_TYPES = frozenset({"std_msgs/msg/Header", "builtin_interfaces/msg/Time"})


@functools.cache
def is_stamped(type_name):
    """Does a message of ``type_name`` (e.g. 'geometry_msgs/msg/PoseArray') begin with a stamp
    (a Header or a Time)? False for a type the Jazzy type store does not know.

    >>> is_stamped("geometry_msgs/msg/WrenchStamped"), is_stamped("std_msgs/msg/String")
    (True, False)
    """
    from rosbags.typesys import Stores, get_typestore
    fields = get_typestore(Stores.ROS2_JAZZY).fielddefs.get(type_name)
    if not fields or not fields[1]:
        return False
    kind, name = fields[1][0][1]
    return isinstance(name, str) and name in STAMP_TYPES


def stamp_ns(data):
    """The stamp [ns] at the start of a serialized stamped message (CDR, either byte order):
    its Header's stamp or its Time.

    >>> stamp_ns(bytes([0, 1, 0, 0]) + struct.pack("<iI", 3, 5))
    3000000005
    """
    order = "<" if data[1] == 1 else ">"
    sec, nanosec = struct.unpack_from(order + "iI", data, 4)
    return sec * NS_PER_S + nanosec


class SimLogTime:
    """Log time [ns] of each recorded message: :meth:`of` (type name, CDR bytes, the
    recorder's clock [ns]) gives the message's stamp, or for a message without one the latest
    stamp seen so far or the clock, whichever is later."""

    def __init__(self):
        self.latest_ns = 0

    def of(self, type_name, data, clock_ns=0):
        """The log time of one message [ns]."""
        if is_stamped(type_name):
            ns = stamp_ns(data)
            self.latest_ns = max(self.latest_ns, ns)
            return ns
        return max(self.latest_ns, int(clock_ns))
