"""motoflex_ros: lumped stiffness identification of motorcycle components and weave/wobble.

Reference: F. Passigato, A. Schramm, S. Sorrentino, A. De Felice, A. Gordner, F. Diermeyer,
"Identification of lumped stiffness parameters for a motorcycle model in investigating weave
and wobble", Multibody System Dynamics (2023). Equation numbers in docstrings are the paper's.

Layers, bottom to top (docs/architecture.md; the import contract in pyproject.toml):

- base: ``errors``; ``units``, ``frames``, ``spatial``, ``progress``, ``files`` (atomic writes),
  ``limits``, ``inertia``; ``input_pins`` (a run pinned to its inputs); ``config`` (YAML).
- ``lumped_stiffness``: the lumped model's formulas, eqs. (1)-(8) and (12).
- ``structures``: FE components and their reduction.
- ``identify`` (eqs. 1-12 on measurements) beside ``vehicle`` (the multibody engine).
- ``bench``: the virtual bench and its campaign; ``study``: the studies (eqs. 13-18).
- edges: ``formats`` (file formats), ``record`` (bags, rerun) and ``plots`` (matplotlib),
  ``nodes`` (rclpy), ``launcher`` (processes), ``report`` (HTML) and ``cli`` (``motoflex``).
"""
__version__ = "0.1.0"
