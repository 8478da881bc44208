"""The vehicle_simulator's stability over speed: weave, wobble and capsize eigenvalues from
the core's modal sweep, as a DiagnosticArray (/vehicle/eigenvalues, stamped at the start of the
road test on the run's clock) and as arrays a plot panel draws against speed
(/vehicle/modes/speed_kmh and /vehicle/modes/<mode>/{frequency_hz, real_part},
std_msgs/Float64MultiArray, latched).
"""
from diagnostic_msgs.msg import DiagnosticArray
from std_msgs.msg import Float64MultiArray

from motoflex_ros.nodes.interfaces import LATCHED, LATCHED_LAST, Topic
from motoflex_ros.nodes.qos_profiles import latched_qos
from motoflex_ros.nodes.result_messages import mode_series, mode_statuses
from motoflex_ros.nodes.stamps import time_msg

__all__ = ["ModePublisher", "MODE_TOPICS"]

MODE_TOPICS = (
    Topic("pub", "vehicle/eigenvalues", "diagnostic_msgs/msg/DiagnosticArray", LATCHED,
          "weave, wobble and capsize over speed (KeyValue JSON lists speeds_kmh, real "
          "[1/s], frequency_hz), tracked by mode shape"),
    Topic("pub", "vehicle/modes/speed_kmh", "std_msgs/msg/Float64MultiArray", LATCHED_LAST,
          "the speeds of the sweep [km/h]", when="after the sweep"),
    Topic("pub", "vehicle/modes/{c}/frequency_hz", "std_msgs/msg/Float64MultiArray",
          LATCHED_LAST, "a mode's frequency over speed [Hz] ({c}: weave, wobble, capsize)",
          when="after the sweep"),
    Topic("pub", "vehicle/modes/{c}/real_part", "std_msgs/msg/Float64MultiArray",
          LATCHED_LAST, "a mode's real part over speed [1/s] ({c}: weave, wobble, capsize)",
          when="after the sweep"),
)


class ModePublisher:
    """The sweep's publishers on ``node`` (the series' ones when there is a sweep)."""

    def __init__(self, node):
        self.node = node
        self.eigenvalues = node.create_publisher(DiagnosticArray, "vehicle/eigenvalues",
                                                 latched_qos())
        self.series = []

    def publish(self, speeds, modes, ns):
        """The modes {name: eigenvalues (n,) [1/s]} at ``speeds`` [m/s], stamped ``ns``."""
        eig = DiagnosticArray(status=mode_statuses(speeds, modes))
        eig.header.stamp = time_msg(ns)
        self.eigenvalues.publish(eig)
        for name, series in mode_series(speeds, modes).items():
            pub = self.node.create_publisher(Float64MultiArray, f"vehicle/modes/{name}",
                                             latched_qos(1))
            pub.publish(series)
            self.series.append(pub)
