"""Why a run failed, in words: the exception and the checks the launcher and its monitor share.

Below :mod:`.run` and :mod:`.monitor` (each imports it; neither imports the other's failures).
"""
import os

from motoflex_ros.errors import MotoflexError
from motoflex_ros.launcher.domain import participants_in_domain
from motoflex_ros.launcher.graph import describe_exit
from motoflex_ros.nodes.dds import peers_range

__all__ = ["RunFailed", "peer_room_problem", "check_peer_room", "pacer_failed"]


class RunFailed(MotoflexError):
    """The run could not finish (a node died, did not come up, or failed)."""


def peer_room_problem(domain_id, ours=0):
    """Why the run's ``ours`` participants would not all discover each other in the domain
    (the loopback profile reaches the first maxInitialPeersRange participant ids only), in
    words; None when they fit (or another profile decides discovery)."""
    reach, profile = peers_range(os.environ)
    if reach is None:
        return None
    others = participants_in_domain(domain_id)
    if others + ours <= reach:
        return None
    return (f"ROS_DOMAIN_ID {domain_id} has {others} DDS participants on this host; with this "
            f"run's {ours} that is above the {reach} the loopback profile's "
            f"maxInitialPeersRange lets discovery reach ({profile}): the nodes would not find "
            f"each other. Use another ROS_DOMAIN_ID (or leave it unset for a free one)")


def check_peer_room(domain_id, ours):
    """RunFailed at once when :func:`peer_room_problem` finds the domain too full."""
    problem = peer_room_problem(domain_id, ours)
    if problem:
        raise RunFailed(problem)


def pacer_failed(graph, pacer, code):
    """RunFailed for a pacing node that ended with ``code``."""
    verb = "died" if code < 0 else "failed"
    full = peer_room_problem(graph.domain_id)   # others joined the domain during the run
    return RunFailed(f"node '{pacer}' {verb} ({describe_exit(code)}); its log: "
                     f"{graph.log_dir / (pacer + '.log')}: {graph.log_tail(pacer)}"
                     + (f"; likely cause: {full}" if full else ""))
