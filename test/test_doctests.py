"""The examples in the docstrings of identify/ and study/ run as tests.

Each public formula of the paper's eqs. 1-18 carries a doctest computing a small case whose
answer is known in closed form (docs/references.md, [Passigato 2023]); a failing example here
is a formula that no longer gives the analytic value.
"""
import doctest
import importlib
import pkgutil

import pytest

import motoflex_ros.identify
import motoflex_ros.study

MODULES = sorted(f"{package.__name__}.{info.name}"
                 for package in (motoflex_ros.identify, motoflex_ros.study)
                 for info in pkgutil.iter_modules(package.__path__))


@pytest.mark.parametrize("name", MODULES)
def test_docstring_examples(name):
    result = doctest.testmod(importlib.import_module(name), optionflags=doctest.ELLIPSIS,
                             verbose=False, report=True)
    assert result.failed == 0, f"{result.failed} of {result.attempted} examples failed in {name}"


def test_every_paper_formula_has_an_example():
    """The functions implementing eqs. 1-18 each carry at least one example."""
    formulas = {
        "motoflex_ros.lumped_stiffness.axis": ["plane_offset", "joint_position", "joint_distance",
                                       "axis_angle", "moment_arm", "axis_stiffness",
                                       "deformation_axis"],
        "motoflex_ros.identify.decay": ["decay_poles"],
        "motoflex_ros.identify.stiffness": ["natural_frequency", "damping_ratio",
                                            "modal_inertia", "modal_damping", "static_damping"],
        "motoflex_ros.lumped_stiffness.decomposition": ["decompose_stiffness",
                                                "static_stiffness_from_split"],
        "motoflex_ros.identify.peaks": ["wrap_axis", "joint_distance_from_arm"],
        "motoflex_ros.study.stability_index": ["max_real_part", "stable_fraction",
                                               "combined_index", "stability_index"],
        "motoflex_ros.study.correlation": ["pearson"],
        "motoflex_ros.study.accuracy": ["rms_error_percent", "weave_wobble_errors"],
        "motoflex_ros.study.anova": ["anova"],
    }
    finder = doctest.DocTestFinder(recurse=False)
    missing = [f"{module}.{name}" for module, names in formulas.items() for name in names
               if not any(t.examples for t in finder.find(
                   getattr(importlib.import_module(module), name)))]
    assert not missing, f"formulas without an example: {missing}"
