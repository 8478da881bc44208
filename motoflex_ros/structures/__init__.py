"""Finite-element components: Timoshenko beams, sparse assembly, Craig-Bampton reduction.

Pure numpy/scipy; the bench and the vehicle use :func:`load_component` and
:meth:`Component.clamped_reduced` / :meth:`Component.craig_bampton`.

Modules: ``beam`` (Timoshenko element), ``solid`` (solid elements), ``assembly`` (sparse
assembly), ``sparse_solver``, ``craig_bampton``, ``clamped`` (static, modal and state-space
solvers of the reduced model), ``full_model`` (the unreduced check), ``bodies`` (per-body
reductions), ``component_model`` (the chain every component shares; beam components),
``component_schema`` (the YAML schemas), ``component_loader`` (a component by name or file),
``mesh_component``, ``mesh_file`` and ``mesh_examples`` (the engineer's volume meshes),
``superelement_file`` (pre-reduced matrices), ``reduction_cache`` (reductions on disk),
``component_summary`` (headline numbers), ``paper_tables`` (Tables 1 and 2),
``physical_ranges`` (the allowed ranges the schemas share).
"""
from motoflex_ros.structures.clamped import ReducedComponent
from motoflex_ros.structures.component_loader import load_component
from motoflex_ros.structures.component_model import Component

__all__ = ["Component", "ReducedComponent", "load_component"]
