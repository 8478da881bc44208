"""The rig's two QoS profiles: reliable keep-all for the data, reliable latched for state.

Their descriptions for ``--help`` and docs/ros-interfaces.md are :data:`.interfaces.RELIABLE`
and :data:`.interfaces.LATCHED`.
"""
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy

__all__ = ["reliable_qos", "latched_qos"]


def reliable_qos():
    """Reliable, keep-all, volatile: nothing is dropped, the writer waits for the reader."""
    return QoSProfile(depth=1, history=HistoryPolicy.KEEP_ALL,
                      reliability=ReliabilityPolicy.RELIABLE,
                      durability=DurabilityPolicy.VOLATILE)


def latched_qos(depth=100):
    """Reliable, transient-local: late subscribers get the last ``depth`` messages."""
    return QoSProfile(depth=depth, history=HistoryPolicy.KEEP_LAST,
                      reliability=ReliabilityPolicy.RELIABLE,
                      durability=DurabilityPolicy.TRANSIENT_LOCAL)
