"""``motoflex rerun BAG``: convert a recorded run into its rerun recording BAG/<run>.rrd."""
from pathlib import Path

from motoflex_ros.cli.output import add_force_option, check_new_file
from motoflex_ros.cli.recording import MODE_SPEED_KMH, write_recording
from motoflex_ros.errors import ConfigError

__all__ = ["register", "run"]


def register(subparsers):
    parser = subparsers.add_parser(
        "rerun", help="convert a recorded bag into a rerun recording (.rrd)",
        description="Convert a recorded run (rosbag2 MCAP directory bags/<run>) into "
                    "bags/<run>/<run>.rrd: bench components with loads, deformed shapes and "
                    "deformation axes, identification, vehicle. Open it with 'motoflex view'.")
    parser.add_argument("bag", type=Path, help="run folder bags/<run> (metadata.yaml + .mcap)")
    parser.add_argument("--out", type=Path, default=None,
                        help="output .rrd (default: <bag>/<run>.rrd, replaced when it exists; "
                             "an existing --out only with --force)")
    add_force_option(parser)
    parser.add_argument("--vehicle", default="touring",
                        help="shipped vehicle drawn with its modes and road test, or 'none' "
                             "(default: touring; its lumped 'static' variant when the run "
                             "folder holds identification results)")
    parser.add_argument("--mode-speed-kmh", type=float, default=MODE_SPEED_KMH, metavar="V",
                        help="speed of the animated weave and wobble and of the road test "
                             "[km/h], in (0, 400]")
    parser.set_defaults(func=run)


def run(args):
    if not 0.0 < args.mode_speed_kmh <= 400.0:
        raise ConfigError("command line", "--mode-speed-kmh",
                          f"must be in (0, 400] km/h, got {args.mode_speed_kmh:g}")
    if args.out is not None:
        if args.out.suffix != ".rrd":   # the viewer and `rerun rrd verify` go by the suffix
            raise ConfigError("command line", "--out",
                              f"a rerun recording ends in .rrd, got {str(args.out)!r}")
        check_new_file(args.out, args.force)
    vehicle = None if args.vehicle == "none" else args.vehicle
    path, converted = write_recording(args.bag, args.out, vehicle, progress=True,
                                      speed_kmh=args.mode_speed_kmh)
    print(f"wrote {path}")
    for item in converted:
        print(f"  {item}")
    return 0
