"""Finite-element components: Timoshenko beams, sparse assembly, Craig-Bampton reduction.

Pure numpy/scipy; the bench and the vehicle take a built component (read from its file at the
edge, :func:`motoflex_ros.formats.component_file.load_component`) and call
:meth:`Component.clamped_reduced` / :meth:`Component.craig_bampton`.

Modules: ``beam`` (Timoshenko element), ``solid`` (solid elements), ``assembly`` (sparse
assembly), ``sparse_solver``, ``craig_bampton``, ``clamped`` (static, modal and state-space
solvers of the reduced model), ``full_model`` (the unreduced check), ``bodies`` (per-body
reductions), ``component_model`` (the chain every component shares; beam components),
``component_schema`` (the beam YAML schemas and the builder from a parsed file),
``mesh_component`` (a component of solid elements and its rigid spiders),
``superelement_component`` (a component given as reduced matrices), ``reduction_cache``
(reductions on disk), ``component_summary`` (headline numbers), ``paper_tables`` (Tables 1 and
2), ``physical_ranges`` (the allowed ranges the schemas share).
"""
from motoflex_ros.structures.clamped import ReducedComponent
from motoflex_ros.structures.component_model import Component

__all__ = ["Component", "ReducedComponent"]
