"""component_simulator: the clamped reduced component under the commanded load.

For each sample (phase + load of /bench/<c>/), steps the core's ComponentSimulator and
publishes the true marker positions on /bench/<c>/markers/true (geometry_msgs/PoseArray,
clamp frame), stamped with the load's time, and the loaded end's motion as the moving frame
<c>_clamp -> <c>_loaded_end on /rig/tf (recorded as /tf; every ``tf_period`` of simulated time).
At start it publishes, latched, the bench's fixed frames (world -> <c>_clamp and
<c>_loaded_end -> <c>_marker_<i> on /rig/tf_static, recorded as /tf_static:
:mod:`motoflex_ros.frames`) and the beam model, members and nodes, as /bench/<c>/structure
(visualization_msgs/MarkerArray, clamp frame). A load that is not
finite, beyond the protocol's range or stamped before the previous one stops the node
(:mod:`.message_checks`).
"""
import sys

import numpy as np
from geometry_msgs.msg import PoseArray, WrenchStamped
from std_msgs.msg import String
from visualization_msgs.msg import MarkerArray

from motoflex_ros.bench.sensor import marker_positions
from motoflex_ros.frames import bench_transforms, loaded_end_transform
from motoflex_ros.nodes.bench_graph import BENCH_PARAMS, SampleJoin, campaign_setups, frame_id
from motoflex_ros.nodes.bench_graph import topic as bench_topic
from motoflex_ros.nodes.cdr import is_end_marker, points_cdr, sample_from_phase
from motoflex_ros.nodes.conversions import structure_markers
from motoflex_ros.nodes.interfaces import (
    LATCHED_LAST,
    LOAD_IN,
    PHASE_IN,
    RELIABLE,
    RIG_TOPICS,
    TF_DYNAMIC,
    TF_STATIC,
    Topic,
)
from motoflex_ros.nodes.message_checks import BenchInputs
from motoflex_ros.nodes.node_main import run_node
from motoflex_ros.nodes.params import Param
from motoflex_ros.nodes.qos_profiles import latched_qos
from motoflex_ros.nodes.rig_node import RigNode
from motoflex_ros.nodes.stamps import seconds_to_ns
from motoflex_ros.nodes.tf import TfPublisher
from motoflex_ros.spatial import rotation_from_vector

__all__ = ["ComponentSimulatorNode", "main"]


class ComponentSimulatorNode(RigNode):
    """Load in, true markers out."""

    NAME = "component_simulator"
    PARAMS = BENCH_PARAMS + (
        Param("tf_period", 0.01, 0.0, 1.0,
              description="the loaded end on /rig/tf every so much simulated time [s] "
                          "(0: every sample)"),
    )
    TOPICS = RIG_TOPICS + (
        PHASE_IN, LOAD_IN,
        Topic("pub", "bench/{c}/markers/true", "geometry_msgs/msg/PoseArray", RELIABLE,
              "true marker positions [m], frame <c>_clamp, stamped with the load's time"),
        Topic("pub", "bench/{c}/structure", "visualization_msgs/msg/MarkerArray", LATCHED_LAST,
              "the beam model (members and nodes), frame <c>_clamp"),
        TF_DYNAMIC, TF_STATIC,
    )

    def __init__(self):
        from motoflex_ros.bench.response import ComponentSimulator
        super().__init__()
        self.setups = campaign_setups(self.params)
        self.sims = {c: ComponentSimulator(s.reduced) for c, s in self.setups.items()}
        self.pubs = {}
        self.tf = TfPublisher(self, dynamic=True)
        for c in self.setups:
            self.pubs[c] = self.advertise(PoseArray, bench_topic(c, "markers/true"))
            join = SampleJoin("phase", ("load",), self._handler(c),
                              needs=lambda head: () if is_end_marker(head) else ("load",))
            self.subscribe(String, bench_topic(c, "phase"), join.callback("phase"), raw=True)
            self.subscribe(WrenchStamped, bench_topic(c, "load"), join.callback("load"),
                           raw=True)
        self._publish_bench()

    def _publish_bench(self):
        """The benches' static frames and each component's beam model (latched)."""
        self.tf.static(bench_transforms([
            (c, s.component.origin, s.reduced.q0, s.protocol.sensor.markers)
            for c, s in self.setups.items()]))
        self.structure_pubs = {}
        for c, s in self.setups.items():
            pub = self.create_publisher(MarkerArray, bench_topic(c, "structure"), latched_qos(1))
            pub.publish(structure_markers(frame_id(c), c, s.component.node_xyz,
                                          s.component.elements))
            self.structure_pubs[c] = pub

    def _handler(self, component):
        setup = self.setups[component]
        q0 = np.asarray(setup.reduced.q0, float)
        offsets = np.asarray(setup.protocol.sensor.markers, float)
        checked = BenchInputs.of_plan(component, setup.plan, self.get_namespace())
        period = seconds_to_ns(self.params["tf_period"])
        next_tf = [0]

        def handle(phase, inputs):
            if "load" not in inputs:
                return
            ns, load = checked.wrench(inputs["load"])
            sample, _ = sample_from_phase(phase, load)
            motion = self.sims[component].step(sample)
            rotation = rotation_from_vector(motion[3:])
            markers = marker_positions(q0 + motion[:3], rotation, q0, offsets)
            self.pubs[component].publish(points_cdr(ns, frame_id(component), markers))
            if ns >= next_tf[0]:
                self.tf.send(ns, [loaded_end_transform(component, q0, rotation, motion[:3])])
                next_tf[0] = ns + period
        return handle


def main(args=None):
    """Console script ``component_simulator``."""
    return run_node(ComponentSimulatorNode, args)


if __name__ == "__main__":
    sys.exit(main())
