"""Figures (matplotlib, Agg backend). Imported lazily by the CLI verbs; the core never imports
this package.

Modules: ``axes`` (Figs. 5-7: deformation axes in the x-z plane), ``component_figure`` (a
clamped component and its first modes), ``accuracy_figure`` (Fig. 9), ``study_figures``
(Figs. 4, 8, 10), ``vehicle`` (root locus, weave/wobble over speed),
``design_front`` (the design study's mass / stability-margin front), ``labels`` (names of
variants and quantities, no matplotlib).
"""
