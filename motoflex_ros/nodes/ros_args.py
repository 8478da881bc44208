"""What a node's ``--ros-args`` give it: params files, ``-p`` names, and who each file's
parameters are for.

rclpy merges every source into one set of overrides; telling them apart needs the command
line. A params file section is keyed by a node name (``sim_clock:``, ``/ns/sim_clock:``, or
nested ``/ns: {sim_clock: ...}``) or by a wildcard (``/**:``, ``/ns/*:``); a parameter under a
wildcard may be meant for another node of the run, one under this node's name is for it.
"""
import yaml

__all__ = ["params_files", "wildcard_only_names"]


def _ros_arg_values(argv, flags):
    """Values following any of ``flags`` inside ``--ros-args`` ... (``--``) blocks."""
    values, inside, tokens = [], False, iter(argv)
    for token in tokens:
        if token == "--ros-args":
            inside = True
        elif token == "--":
            inside = False
        elif inside and token in flags:
            values.append(next(tokens, ""))
    return values


def params_files(argv):
    """Paths given with ``--params-file`` in the ROS arguments of ``argv``."""
    return _ros_arg_values(argv, ("--params-file",))


def _command_line_names(argv):
    """Names of the parameters given with ``-p`` / ``--param name:=value``."""
    return {value.split(":=", 1)[0] for value in _ros_arg_values(argv, ("-p", "--param"))}


def _flat(values, prefix=""):
    """Parameter names of a ``ros__parameters`` mapping (nested keys joined with '.')."""
    names = set()
    for key, value in (values or {}).items():
        name = f"{prefix}{key}"
        names |= _flat(value, f"{name}.") if isinstance(value, dict) else {name}
    return names


def _sections(tree, keys=()):
    """(node key without outer '/', parameter names) of each section of a params file."""
    if not isinstance(tree, dict):
        return
    for key, value in tree.items():
        if key == "ros__parameters":
            yield "/".join(k.strip("/") for k in keys), _flat(value)
        else:
            yield from _sections(value, (*keys, str(key)))


def _section_names(path, node_fqn):
    """({names under this node's name}, {names under a wildcard}) of one params file.

    ``node_fqn`` is the node's fully qualified name ('/sim_clock'). A file that cannot be read
    gives nothing (rclpy.init has refused it already).
    """
    try:
        with open(path, encoding="utf-8") as stream:
            tree = yaml.safe_load(stream)
    except (OSError, yaml.YAMLError):
        tree = None
    named, wildcard = set(), set()
    for key, names in _sections(tree):
        if "*" in key:
            wildcard |= names
        elif key == node_fqn.strip("/"):
            named |= names
    return named, wildcard


def wildcard_only_names(argv, node_fqn):
    """Parameters that only wildcard sections of the params files give: neither a section
    named for the node ``node_fqn`` nor ``-p`` sets them (they may be for another node)."""
    named, wildcard = _command_line_names(argv), set()
    for path in params_files(argv):
        for_node, for_any = _section_names(path, node_fqn)
        named |= for_node
        wildcard |= for_any
    return wildcard - named
