"""Published targets of the paper's components (Passigato et al. 2023, Tables 1 and 2)."""

from motoflex_ros.config import MOTORCYCLE_COMPONENTS

__all__ = ["paper_table1_eigenfrequencies", "paper_table2_stiffness", "COMPONENTS"]

COMPONENTS = MOTORCYCLE_COMPONENTS


def paper_table1_eigenfrequencies():
    """Table 1: first torsion and bending eigenfrequencies [Hz] of the clamped components."""
    return {"frame": {"torsion": 74.0, "bending": 93.0},
            "front_assembly": {"torsion": 28.0, "bending": 79.0},
            "swingarm": {"torsion": 321.0, "bending": 112.0}}


def paper_table2_stiffness():
    """Table 2: k about the static axis and its split k_t, k_b (eq. 12) [N m/rad]."""
    return {"frame": {"k": 1.03e6, "k_t": 3.75e5, "k_b": 3.59e6},
            "front_assembly": {"k": 1.06e4, "k_t": 5.95e3, "k_b": 1.71e5},
            "swingarm": {"k": 1.33e5, "k_t": 1.04e6, "k_b": 1.39e5}}
