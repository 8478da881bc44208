"""Write config/nodes/<node>.yaml from each node's declared parameters (issue 24, point 8).

Usage: python tools/write_node_configs.py   (test/test_nodes_config.py checks the files match)
"""
import importlib
from pathlib import Path

from motoflex_ros.nodes import NODE_CLASSES
from motoflex_ros.nodes.params import parameters_yaml

CONFIG = Path(__file__).resolve().parents[1] / "motoflex_ros" / "config" / "nodes"


def main():
    for name, class_name in NODE_CLASSES.items():
        node_class = getattr(importlib.import_module(f"motoflex_ros.nodes.{name}"), class_name)
        path = CONFIG / f"{name}.yaml"
        path.write_text(parameters_yaml(name, node_class.PARAMS))
        print(f"wrote {path}")


if __name__ == "__main__":
    main()
