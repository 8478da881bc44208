"""ROS 2 nodes of the rig: thin rclpy adapters around the numerical core (no physics here).

One module per executable (``ros2 run motoflex_ros <name>`` or the console script of the same
name); message conversions live in :mod:`.conversions` (message objects), :mod:`.stamps`
(time), :mod:`.cdr` (the bench's messages as bytes) and :mod:`.result_messages`; the ROS
transport in :mod:`.transport`. Every node is a :class:`.rig_node.RigNode` (parameters from
:mod:`.params`, publishers and subscriptions with the QoS of :mod:`.qos_profiles`, readiness)
and every executable's ``main`` is :func:`.node_main.run_node` (its command line checked by
:mod:`.node_command_line`).

Executables: ``sim_clock``, ``recorder``, ``bag_replay``, ``load_actuator``,
``component_simulator``, ``displacement_sensor``, ``identification`` (with
``virtual_identification`` for the virtual bench; ``measured_identification``,
``measured_inputs`` and ``kept_frames`` for a real rig's topics), ``vehicle_simulator`` (with
``mode_publisher``, ``road_publisher`` and ``rig_markers``). Shared: ``bench_graph`` (what the
bench nodes share), ``interfaces`` (topics per node), ``endpoints`` (who may publish to a
node), ``message_checks``, ``pacing`` (lock-step simulated time), ``dds`` (where DDS traffic
may go), ``transport_ctypes`` and ``transport_rclpy`` (the two paths behind ``transport``),
``ros_args``, ``tf``.
"""

# every executable node: module name (= executable, node name) -> its class
NODE_CLASSES = {
    "sim_clock": "SimClock", "recorder": "Recorder", "bag_replay": "BagReplay",
    "load_actuator": "LoadActuatorNode", "component_simulator": "ComponentSimulatorNode",
    "displacement_sensor": "DisplacementSensorNode", "identification": "IdentificationNode",
    "vehicle_simulator": "VehicleSimulatorNode",
}
