"""The lumped stiffness model of a component (Passigato et al. 2023, Sect. 4.2): pure formulas.

Below every other part of the core: the FE components (structures) compute their exact axis
with them, the identification fits them to the bench's measurements.

- :mod:`.axis` eqs. (1)-(8): deformation axis (l, beta, b) and k from a pose of the loaded end.
- :mod:`.decomposition` eqs. (12a)-(12b): k_t, k_b.
- :mod:`.axis_line`: the drawn segment of an identified axis (l, beta) in 3-D.
"""
