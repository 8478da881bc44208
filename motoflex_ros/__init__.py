"""motoflex_ros: lumped stiffness identification of motorcycle components and weave/wobble.

Reference: F. Passigato, A. Schramm, S. Sorrentino, A. De Felice, A. Gordner, F. Diermeyer,
"Identification of lumped stiffness parameters for a motorcycle model in investigating weave
and wobble", Multibody System Dynamics (2023). Equation numbers in docstrings are the paper's.
"""
__version__ = "0.1.0"
