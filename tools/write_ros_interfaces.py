#!/usr/bin/env python3
"""Write the per-node part of docs/ros-interfaces.md from the nodes' own declarations.

Usage: python tools/write_ros_interfaces.py [--check]

Each node's TOPICS (motoflex_ros/nodes/interfaces.py) and PARAMS (motoflex_ros/nodes/params.py)
become its tables, between the page's BEGIN and END markers; the rest of the page is written by
hand. ``--check`` exits 1 when the page is not what the declarations give (the suite runs it,
test/test_node_interfaces.py).
"""
import argparse
import importlib
import sys
from pathlib import Path

from motoflex_ros.nodes import NODE_CLASSES

PAGE = Path(__file__).resolve().parents[1] / "docs" / "ros-interfaces.md"
BEGIN = "<!-- BEGIN nodes: written by tools/write_ros_interfaces.py from the nodes' TOPICS " \
        "and PARAMS; do not edit by hand -->"
END = "<!-- END nodes -->"


def _cell(text):
    return str(text).replace("|", "\\|")


def node_section(name, node_class):
    """Markdown of one node: summary, topics table, parameters table."""
    doc = sys.modules[node_class.__module__].__doc__ or ""
    summary = " ".join(doc.strip().split("\n\n")[0].split())
    lines = [f"### {name}", "", summary, "",
             "| | topic | type | QoS | meaning |", "|---|---|---|---|---|"]
    for t in node_class.TOPICS:
        when = f" (when: {t.when})" if t.when else ""
        lines.append(f"| {t.direction} | `/{_cell(t.name)}` | `{_cell(t.msg_type)}` | "
                     f"{_cell(t.qos)} | {_cell(t.description)}{_cell(when)} |")
    lines += ["", "| parameter | type and range | default | meaning |", "|---|---|---|---|"]
    for p in node_class.PARAMS:
        default = list(p.default) if p.kind == "str[]" else p.default
        lines.append(f"| `{p.name}` | {_cell(p.allowed())} | `{default!r}` | "
                     f"{_cell(p.description)} |")
    return "\n".join(lines) + "\n"


def generated():
    """The text between the markers."""
    sections = []
    for name, class_name in NODE_CLASSES.items():
        node_class = getattr(importlib.import_module(f"motoflex_ros.nodes.{name}"), class_name)
        sections.append(node_section(name, node_class))
    return "\n".join(sections)


def page_with(text, page):
    head, rest = page.split(BEGIN, 1)
    _, tail = rest.split(END, 1)
    return f"{head}{BEGIN}\n{text}{END}{tail}"


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true", help="exit 1 if the page is stale")
    args = parser.parse_args(argv)
    page = PAGE.read_text()
    new = page_with(generated(), page)
    if args.check:
        if new != page:
            print(f"{PAGE}: stale; run python tools/write_ros_interfaces.py", file=sys.stderr)
            return 1
        return 0
    PAGE.write_text(new)
    print(f"wrote {PAGE}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
