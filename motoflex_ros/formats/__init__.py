"""File formats at the edge: what the numerical core computes, written to and read from files.

- :mod:`.json_yaml`: results as plain JSON (``--json``, ``--out``) or YAML, written atomically.

The numerical core (structures, vehicle, identify, bench, study) imports nothing from here
(the import contract in pyproject.toml, docs/architecture.md).
"""
