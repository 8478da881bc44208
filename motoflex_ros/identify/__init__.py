"""Identification of lumped stiffness parameters (Passigato et al. 2023, Sect. 4.2)."""
