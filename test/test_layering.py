"""Layering (issue 16, point 10): the nodes do not depend on the CLI.

Every import of the package's modules is read from the source, the ones inside functions
too, and followed through the package, so a node reaching a CLI module by way of another
module fails as well.
"""
import ast
from pathlib import Path

import motoflex_ros

ROOT = Path(motoflex_ros.__file__).parent


def _module_name(path):
    parts = ("motoflex_ros", *path.relative_to(ROOT).with_suffix("").parts)
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


MODULES = {_module_name(p): p for p in ROOT.rglob("*.py")}


def _with_packages(name):
    """``name`` and the packages an import of it runs first ('a.b.c': 'a', 'a.b', 'a.b.c')."""
    parts = name.split(".")
    return {".".join(parts[:i]) for i in range(1, len(parts) + 1)}


def imports_of(module):
    """The package modules ``module`` imports anywhere in its source."""
    names = set()
    for node in ast.walk(ast.parse(MODULES[module].read_text())):
        if isinstance(node, ast.Import):
            names |= {alias.name for alias in node.names}
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            names |= {node.module} | {f"{node.module}.{alias.name}" for alias in node.names}
    return {m for name in names for m in _with_packages(name) if m in MODULES}


def import_chains(start):
    """{module: the chain of imports from ``start`` to it} for every module ``start`` reaches."""
    chains, todo = {start: (start,)}, [start]
    while todo:
        module = todo.pop()
        for imported in sorted(imports_of(module) - set(chains)):
            chains[imported] = (*chains[module], imported)
            todo.append(imported)
    return chains


def test_import_chains_follow_function_level_imports():
    chains = import_chains("motoflex_ros.record.rerun_bag_vehicle")
    # rerun_bag_vehicle imports rerun_motorcycle only inside a function
    assert chains["motoflex_ros.record.rerun_motorcycle"] == (
        "motoflex_ros.record.rerun_bag_vehicle", "motoflex_ros.record.rerun_motorcycle")


def test_nodes_do_not_import_the_cli():
    nodes = [m for m in MODULES if m.startswith("motoflex_ros.nodes.")]
    assert "motoflex_ros.nodes.identification" in nodes
    reached = [" -> ".join(chain) for node in nodes
               for module, chain in import_chains(node).items()
               if module.startswith("motoflex_ros.cli")]
    assert not reached, reached


def _package_modules(package):
    return [m for m in MODULES if m == package or m.startswith(package + ".")]


def test_vehicle_takes_lumped_parameters_and_does_not_import_the_identification():
    """Issue 12: the vehicle gets lumped joints (FlexJoint) and superelements; reading
    identification results into them is the study layer's job (study/variants.py)."""
    direct = [f"{m} imports {i}" for m in _package_modules("motoflex_ros.vehicle")
              for i in imports_of(m)
              if i.startswith(("motoflex_ros.identify", "motoflex_ros.study",
                               "motoflex_ros.bench"))]
    assert not direct, direct


def test_structures_stand_below_the_vehicle():
    """Issue 12: structures reach neither the vehicle nor the studies (shared mass-property
    checks live in motoflex_ros.inertia)."""
    reached = [" -> ".join(chain) for m in _package_modules("motoflex_ros.structures")
               for module, chain in import_chains(m).items()
               if module.startswith(("motoflex_ros.vehicle", "motoflex_ros.study"))]
    assert not reached, reached


ENGINES = ("motoflex_ros.vehicle.linearize", "motoflex_ros.vehicle.modes",
           "motoflex_ros.vehicle.response", "motoflex_ros.bench.response",
           "motoflex_ros.study")


def test_record_layer_is_handed_what_it_draws():
    """Issue 16, point 10: record/ writes what the core computed (the motorcycle's motion,
    vehicle.animation; the bench replay, bench.replay) and runs no engine itself: no record
    module reaches a linearization, a modal sweep, a response, the component simulator or a
    study but through those two."""
    allowed = {"motoflex_ros.vehicle.animation", "motoflex_ros.bench.replay"}
    for module in (m for m in MODULES if m.startswith("motoflex_ros.record.")):
        direct = imports_of(module) - allowed
        reached = {m for d in direct for m in import_chains(d)}
        engines = sorted(m for m in reached | direct
                         if any(m == e or m.startswith(e + ".") for e in ENGINES))
        assert engines == [], (module, engines)
