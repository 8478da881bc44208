"""Virtual bench: test protocols, time response of the clamped component, marker sensing.

The campaign is a chain of stage objects, each stepped one sample at a time, so that the offline
command and the ROS 2 graph drive exactly the same code (docs/architecture.md):

``LoadActuator`` (protocol samples with phase labels) -> ``ComponentSimulator`` (exact
discretisation of the clamped reduced component) -> ``MarkerSensor`` (markers, noise,
resolution, latency, rigid fit) -> :class:`motoflex_ros.identify.identifier.Identifier`.
"""
