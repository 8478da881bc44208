"""``motoflex replay BAG [--rate R]``: republish a recorded run with its /clock.

Runs the bag_replay node in this process, on the current ROS_DOMAIN_ID, so that other nodes
(a viewer, the identification node) can listen. ``--rate 0`` publishes as fast as possible.
"""
__all__ = ["register", "run"]


def register(subparsers):
    """Add the ``replay`` verb."""
    parser = subparsers.add_parser(
        "replay", help="republish a recorded bag with its /clock",
        description="Republish every topic of a bag (its /clock included) in recording order.")
    parser.add_argument("bag", help="bag directory, e.g. bags/<run>")
    parser.add_argument("--rate", type=float, default=1.0,
                        help="speed factor against the recorded time (0: as fast as possible)")
    parser.set_defaults(func=run)


def run(args):
    """Check the bag, then run bag_replay until every message is out."""
    from motoflex_ros.errors import MotoflexError
    from motoflex_ros.record.mcap_bag import bag_info
    if not 0.0 <= args.rate <= 1000.0:
        raise MotoflexError(f"--rate {args.rate:g} is out of range [0, 1000]")
    info = bag_info(args.bag)
    from motoflex_ros.nodes.bag_replay import BagReplay
    from motoflex_ros.nodes.runtime import run_node
    print(f"replaying {info.path}: {info.message_count} messages at rate {args.rate:g}")
    return run_node(BagReplay, ["motoflex_replay", "--ros-args", "-p", f"bag:={info.path}",
                                "-p", f"rate:={args.rate!r}"])
