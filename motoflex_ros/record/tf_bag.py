"""/tf and /tf_static in the bag as tf2_msgs/msg/TFMessage, from the rig's TransformStamped.

There is no tf2_msgs wheel for ROS 2 Jazzy on PyPI, so rclpy here cannot publish a TFMessage.
The nodes publish each transform as a geometry_msgs/TransformStamped on ``/rig/tf`` (reliable,
keep all) and ``/rig/tf_static`` (transient local); the recorder writes them into the bag as
``/tf`` and ``/tf_static`` of type tf2_msgs/msg/TFMessage, the standard tf topics that
Foxglove, rviz (``ros2 bag play``) and rosbags read: :class:`TfBatcher` gathers the transforms
of one stamp that arrive together into one TFMessage, as a tf broadcaster sends them. The CDR
is decoded and encoded with the rosbags type store (which knows tf2_msgs); no rclpy here.
"""
import functools

__all__ = ["TF_LIVE", "TF_STATIC_LIVE", "TF_TOPICS", "TF_TYPE", "LIVE_TYPE", "TfBatcher"]

TF_LIVE = "rig/tf"                # relative: under the node's namespace
TF_STATIC_LIVE = "rig/tf_static"
TF_TOPICS = {"/rig/tf": "/tf", "/rig/tf_static": "/tf_static"}   # live (rig root) -> bag
TF_TYPE = "tf2_msgs/msg/TFMessage"
LIVE_TYPE = "geometry_msgs/msg/TransformStamped"


@functools.cache
def _typestore():
    from rosbags.typesys import Stores, get_typestore
    return get_typestore(Stores.ROS2_JAZZY)


class TfBatcher:
    """TransformStamped CDR in, TFMessage CDR out: ``add`` the transforms as they arrive
    (receive time [ns], CDR bytes); ``write(log_time_ns, cdr)`` is called with one TFMessage
    per run of equal stamps, at a change of stamp and at each :meth:`flush` (the recorder
    flushes after every burst, so a static transform reaches the bag when it arrives)."""

    def __init__(self, write):
        self.write = write
        self._pending = []
        self._stamp = None
        self._log_ns = None

    def add(self, log_time_ns, data):
        """Queue one serialized geometry_msgs/TransformStamped."""
        store = _typestore()
        msg = store.deserialize_cdr(bytes(data), LIVE_TYPE)
        stamp = (msg.header.stamp.sec, msg.header.stamp.nanosec)
        if self._pending and stamp != self._stamp:
            self.flush()
        if not self._pending:
            self._stamp, self._log_ns = stamp, log_time_ns
        self._pending.append(msg)

    def flush(self):
        """Write the queued transforms as one TFMessage (nothing if none are queued)."""
        if not self._pending:
            return
        store = _typestore()
        tf_class = store.types[TF_TYPE]
        data = store.serialize_cdr(tf_class(transforms=self._pending), TF_TYPE)
        self._pending = []
        self.write(self._log_ns, bytes(data))
