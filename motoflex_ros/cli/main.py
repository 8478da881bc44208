"""Entry point of the ``motoflex`` command.

Each verb is one module in this package exposing ``register(subparsers)``, which adds its parser
and sets ``func`` (called with the parsed arguments, returns an exit code). User errors
(:class:`motoflex_ros.errors.MotoflexError`) are printed as one line, without a traceback, with
exit code 2. Ctrl-C exits with 130.
"""
import argparse
import importlib
import os
import sys

from motoflex_ros.cli.options import state_defaults
from motoflex_ros.errors import MotoflexError
from motoflex_ros.limits import LIMITS, parse_limit, set_limit

__all__ = ["main", "VERBS"]

# verb module names, in the order --help lists them; a module that is absent is skipped
VERBS = ("components", "identify", "compare", "eig", "study", "campaign", "replay", "bag",
         "rerun", "view", "report")


def build_parser():
    parser = argparse.ArgumentParser(
        prog="motoflex",
        description="Virtual test rig for motorcycle chassis engineers: finite-element "
                    "components, bench identification of lumped stiffness models "
                    "(Passigato et al. 2023) and weave/wobble stability.")
    subparsers = parser.add_subparsers(dest="verb", metavar="VERB")
    subparsers.required = True
    for verb in VERBS:
        try:
            module = importlib.import_module(f"motoflex_ros.cli.{verb}")
        except ModuleNotFoundError as exc:
            if exc.name == f"motoflex_ros.cli.{verb}":
                continue
            raise
        module.register(subparsers)
    _add_limit_option(subparsers)
    state_defaults(parser)
    return parser


def _limit_argument(text):
    """Type of --limit: NAME=VALUE (motoflex_ros.limits)."""
    try:
        return parse_limit(text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None


def _add_limit_option(subparsers):
    """--limit NAME=VALUE on every verb (on the leaves of nested verbs such as study)."""
    for sub in subparsers.choices.values():
        nested = [a for a in sub._actions if isinstance(a, argparse._SubParsersAction)]
        if nested:
            _add_limit_option(nested[0])
            continue
        sub.add_argument("--limit", action="append", default=[], type=_limit_argument,
                         metavar="NAME=VALUE",
                         help="raise a limit on the work an input may ask for: "
                              + ", ".join(f"{n} (default {lim.default:g} {lim.unit})"
                                          for n, lim in LIMITS.items()) + "; repeatable")


def main(argv=None):
    parser = build_parser()
    args = parser.parse_args(argv)
    args.argv = list(sys.argv[1:] if argv is None else argv)   # the command, for provenance
    for name, value in getattr(args, "limit", []):
        set_limit(name, value)
    try:
        code = args.func(args)
    except MotoflexError as exc:
        print(f"motoflex {args.verb}: error: {exc}", file=sys.stderr)
        return 2
    except MemoryError:
        print(f"motoflex {args.verb}: error: out of memory: the input asks for more than this "
              f"machine holds (a --limit raised too far?)", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print(f"motoflex {args.verb}: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:
        # the reader went away (e.g. `motoflex bag info ... | head`): stop quietly
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0
    except OSError as exc:
        # a file or folder the user named cannot be read or written
        print(f"motoflex {args.verb}: error: {exc}", file=sys.stderr)
        return 2
    return int(code or 0)


if __name__ == "__main__":
    sys.exit(main())
