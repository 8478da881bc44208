"""Physical ranges of a component's numbers (SI), shared by the beam and the mesh schemas.

Wide enough for any metal, composite or polymer component on a bench, narrow enough that no
value overflows the stiffness and mass matrices (E = 1e300 made the interior stiffness singular)
or underflows a section (an outer diameter of 1e6 m with a 0.04 m tube gave a division by zero).
"""

__all__ = ["MODULUS_PA", "DENSITY", "COMPONENT_SIZE_M", "PART_MASS_MAX_KG", "PART_INERTIA_MAX"]

MODULUS_PA = (1e5, 1e15)  # foam to 5,000 x steel (a nearly rigid modelling material)
DENSITY = (1.0, 1e5)  # [kg/m^3]
COMPONENT_SIZE_M = 10.0  # coordinates and lengths of a component [m]
PART_MASS_MAX_KG = 1e4  # a rigid part's mass [kg]
PART_INERTIA_MAX = 1e4  # a rigid part's principal inertia [kg m^2]
