"""Options shared by the verbs: one list style, unit-named flags, defaults in --help.

- Lists: a repeatable option (``--component NAME --component NAME``), as ``identify`` and
  ``components`` always had. The older forms (eig's comma-separated ``--components a,b``,
  campaign's space-separated ``--components a b``) keep working with a deprecation warning.
- Units in the flag's name: ``--speeds-ms``, ``--speeds-kmh``, ``--range-kmh``, ``--step-kmh``,
  ``--range-rel``; the old ``--speeds`` (m/s), ``--step`` and ``--range`` warn and map to them.
- Defaults: :func:`state_defaults` appends "(default: X)" to every option's help that does not
  state its default already.
"""
import argparse
import sys

__all__ = ["add_component_option", "deprecated", "state_defaults", "components_of"]


def _warn(old, new):
    sys.stderr.write(f"motoflex: warning: {old} is deprecated; use {new}\n")


def deprecated(new, split_commas=False, extend=False):
    """An argparse Action for an old flag: warns once per use, then stores (or, with
    ``extend``, adds to the list) what the new flag ``new`` would (the same ``dest``). Give the
    old flag ``default=argparse.SUPPRESS`` so that the new flag's default stands."""

    class Deprecated(argparse.Action):
        def __call__(self, parser, namespace, values, option_string=None):
            _warn(option_string, new)
            if split_commas:
                values = [v for item in values for v in str(item).split(",") if v]
            if extend:
                current = getattr(namespace, self.dest, None) or []
                values = list(current) + list(values)
            setattr(namespace, self.dest, values)

    return Deprecated


def add_component_option(parser, help_text, metavar="NAME"):
    """``--component NAME`` (repeatable) into ``dest='component'`` (None when not given), and
    the deprecated ``--components`` (comma- or space-separated) into the same list."""
    parser.add_argument("--component", action="append", metavar=metavar, help=help_text)
    parser.add_argument("--components", nargs="+", dest="component", metavar=metavar,
                        action=deprecated("--component NAME (repeatable)", split_commas=True,
                                          extend=True),
                        help=argparse.SUPPRESS, default=argparse.SUPPRESS)


def components_of(args, default):
    """The components asked for (``--component``), or ``default``; 'all' means ``default``."""
    names = args.component or list(default)
    return list(default) if names == ["all"] else names


def _shows_default(action):
    text = (action.help or "").lower()
    return "default" in text


def state_defaults(parser):
    """Append "(default: X)" to the help of every option of ``parser`` and its sub-parsers
    that takes a value whose default is a value (not None, False or an empty list) and whose
    help does not say. A flag (store_true, store_false: no value) is off unless given, which
    its help says; its ``dest`` default (True for --no-compute) is no default to show."""
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for sub in action.choices.values():
                state_defaults(sub)
            continue
        if action.help in (None, argparse.SUPPRESS) or not action.option_strings \
                or action.nargs == 0:
            continue
        default = action.default
        if default is None or default is False or default == [] or default is argparse.SUPPRESS:
            continue
        if not _shows_default(action):
            shown = " ".join(map(str, default)) if isinstance(default, (list, tuple)) \
                else default
            action.help = f"{action.help} (default: {shown})"
