"""Virtual bench: test protocols, time response of the clamped component, marker sensing.

The campaign is a chain of stage objects, each stepped one sample at a time, so that the offline
command and the ROS 2 graph drive exactly the same code (docs/architecture.md):

``LoadActuator`` (protocol samples with phase labels) -> ``ComponentSimulator`` (exact
discretisation of the clamped reduced component) -> ``MarkerSensor`` (markers, noise,
resolution, latency, rigid fit) -> :class:`motoflex_ros.identify.identifier.Identifier`.

Modules: ``plan`` (a protocol planned for one component), ``actuator`` (the planned load
stream), ``response`` and ``clamped_modes`` (the clamped reduced component in time and its
eigenvalues), ``sensor`` (markers and the rigid fit), ``offline_campaign`` (the four stages
driven offline), ``load_tests`` (tests loading a component as the vehicle does), ``export``
(the measurements as a real rig hands them over), ``replayed_loads`` (the component re-run on a
bag's load history), ``protocols`` (the YAML test protocols).
"""
