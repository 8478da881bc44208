"""What the bench nodes share: parameters, topic names, the campaign setups, the sample join.

Every bench node handles the components listed in ``components`` (one campaign after the
other, in that order). Per component the topics are ``/bench/<component>/{load, phase,
markers/true, markers/measured, pose}``. Each sample travels as one message per topic, so the
k-th message on each topic of a component belongs to the same sample: :class:`SampleJoin` pairs
them by arrival count (the DDS order of one topic is kept; the order across topics is not).
The phase message ends a component's campaign with an end marker.
"""
from collections import deque

from motoflex_ros.bench.sensor import MAX_NOISE_M, MAX_SEED
from motoflex_ros.config import MOTORCYCLE_COMPONENTS
from motoflex_ros.frames import clamp_frame
from motoflex_ros.nodes.params import Param

__all__ = ["BENCH_PARAMS", "topic", "frame_id", "campaign_setups", "SampleJoin"]

COMPONENTS = MOTORCYCLE_COMPONENTS

BENCH_PARAMS = (
    Param("components", COMPONENTS, description="components (shipped names or YAML files), in "
                                                "campaign order"),
    Param("protocol", "", description="protocol name or file ('': each component's own)"),
    Param("noise", -1.0, -1.0, MAX_NOISE_M,
          description="sensor noise std [m] (-1: the protocol's)"),
    Param("seed", 0, 0, MAX_SEED, description="seed of the sensor noise"),
)


def topic(component, leaf):
    """bench/<component>/<leaf> (relative: under the node's namespace)."""
    return f"bench/{component}/{leaf}"


def frame_id(component):
    """Frame of a component's bench data: its clamp (REP-103 axes; :mod:`motoflex_ros.frames`)."""
    return clamp_frame(component)


def campaign_setups(params, inputs=None):
    """{component: CampaignSetup} from the bench parameters (the same calls as offline
    ``motoflex identify``: the principal hinges' carried inertia from the vehicle file).

    ``inputs``, a dict, receives {component: {absolute path: SHA-256}} of the files each
    setup read (checked against the run's pins: :mod:`motoflex_ros.input_pins`)."""
    from dataclasses import replace

    from motoflex_ros.bench.offline_campaign import checked_noise, setup_campaign
    from motoflex_ros.formats.component_file import load_component
    from motoflex_ros.input_pins import recording_inputs
    from motoflex_ros.study.identified_variants import carried_inertias
    noise = None if params["noise"] == -1.0 else checked_noise(params["noise"], "ROS parameters",
                                                               "noise")
    protocol = params["protocol"] or None
    setups = {}
    for given in params["components"]:
        with recording_inputs() as read:   # the component, its protocol and the vehicle file
            component = load_component(given)
            carried = carried_inertias([component])
            setup = setup_campaign(component, protocol, noise)
        setup = replace(setup, carried=carried.get(setup.name))
        # keyed by the component's own name (a YAML file's too: its topics are /bench/<name>/)
        setups[setup.name] = setup
        if inputs is not None:
            inputs[setup.name] = dict(sorted(read.items()))
    return setups


class SampleJoin:
    """Pairs the k-th messages of several topics of one component.

    ``push(topic, msg)`` queues a message; whenever the head of the ``primary`` queue and the
    messages it needs (``needs(head)`` -> topics) are all there, ``handler(head, {topic: msg})``
    is called, in order.
    """

    def __init__(self, primary, topics, handler, needs=None):
        self.primary = primary
        self.queues = {t: deque() for t in (primary, *topics)}
        self.handler = handler
        self.needs = needs or (lambda head: topics)

    def push(self, name, msg):
        """Queue ``msg`` of topic ``name`` and handle every complete sample."""
        self.queues[name].append(msg)
        primary = self.queues[self.primary]
        while primary:
            needed = self.needs(primary[0])
            if not all(self.queues[t] for t in needed):
                return
            head = primary.popleft()
            self.handler(head, {t: self.queues[t].popleft() for t in needed})

    def callback(self, name):
        """Subscription callback that pushes to ``name``."""
        return lambda msg: self.push(name, msg)
