"""Finite-element components: Timoshenko beams, sparse assembly, Craig-Bampton reduction.

Pure numpy/scipy; the bench and the vehicle use :func:`load_component` and
:meth:`Component.clamped_reduced` / :meth:`Component.craig_bampton`.
"""
from motoflex_ros.structures.clamped import ReducedComponent
from motoflex_ros.structures.component_loader import load_component
from motoflex_ros.structures.component_model import Component

__all__ = ["Component", "ReducedComponent", "load_component"]
