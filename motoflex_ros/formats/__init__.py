"""File formats at the edge: what the numerical core computes, written to and read from files.

- :mod:`.json_yaml`: results as plain JSON (``--json``, ``--out``) or YAML, written atomically.
- :mod:`.measured_csv`: the measured CSV of a real rig (load and markers per row), read into
  :class:`motoflex_ros.identify.measurements.Measurements` and written from them.

The numerical core (structures, vehicle, identify, bench, study) imports nothing from here: the
layer contract in pyproject.toml puts this package above them (docs/architecture.md).
"""
