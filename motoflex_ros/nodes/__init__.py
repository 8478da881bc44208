"""ROS 2 nodes of the rig: thin rclpy adapters around the numerical core (no physics here).

One module per executable (``ros2 run motoflex_ros <name>`` or the console script of the same
name); message conversions live in :mod:`.conversions` (message objects), :mod:`.stamps`
(time), :mod:`.cdr` (the bench's messages as bytes) and :mod:`.result_messages`; the ROS
transport in :mod:`.transport`; shared plumbing in :mod:`.runtime` and :mod:`.params`.
"""

# every executable node: module name (= executable, node name) -> its class
NODE_CLASSES = {
    "sim_clock": "SimClock", "recorder": "Recorder", "bag_replay": "BagReplay",
    "load_actuator": "LoadActuatorNode", "component_simulator": "ComponentSimulatorNode",
    "displacement_sensor": "DisplacementSensorNode", "identification": "IdentificationNode",
    "vehicle_simulator": "VehicleSimulatorNode",
}
