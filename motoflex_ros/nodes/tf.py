"""The rig's transforms on /rig/tf and /rig/tf_static (geometry_msgs/TransformStamped).

The tree and its frames are :mod:`motoflex_ros.frames`; the recorder writes these topics into
the bag as the standard /tf and /tf_static (tf2_msgs/msg/TFMessage, :mod:`motoflex_ros.record.
tf_bag`: rclpy from PyPI has no tf2_msgs).
"""
from geometry_msgs.msg import TransformStamped

from motoflex_ros.nodes.conversions import transform_msg
from motoflex_ros.nodes.qos_profiles import latched_qos
from motoflex_ros.nodes.transport import publish_patiently
from motoflex_ros.record.tf_bag import TF_LIVE, TF_STATIC_LIVE

__all__ = ["TfPublisher"]
STATIC_DEPTH = 1000   # static transforms a late subscriber still gets (one per message)


class TfPublisher:
    """Publishes FrameTransforms of a node: static ones (latched) and ones along time."""

    def __init__(self, node, dynamic=False):
        self._static = node.create_publisher(TransformStamped, TF_STATIC_LIVE,
                                             latched_qos(STATIC_DEPTH))
        self._dynamic = node.advertise(TransformStamped, TF_LIVE) if dynamic else None

    def static(self, transforms):
        """Publish static transforms (stamp 0)."""
        for transform in transforms:
            self._static.publish(transform_msg(0, transform))

    def send(self, ns, transforms):
        """Publish the transforms of simulated time ``ns`` [ns] on /rig/tf."""
        for transform in transforms:
            publish_patiently(self._dynamic, transform_msg(ns, transform))
