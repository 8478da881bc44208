"""File formats at the edge: what the numerical core computes, written to and read from files.

- :mod:`.json_yaml`: results as plain JSON (``--json``, ``--out``) or YAML, written atomically
  and read back (``--identified``, ``result_file``).
- :mod:`.measured_csv`: the measured CSV of a real rig (load and markers per row), read into
  :class:`motoflex_ros.identify.measurements.Measurements` and written from them.
- :mod:`.bench_file`: a real rig's bench file (YAML: q0, markers, sensor, carried inertia), read
  into :class:`motoflex_ros.identify.physical_bench.PhysicalBench`.
- :mod:`.component_file`: a component by name or YAML file (tube, beam structure, mesh,
  superelement), built into the core's component classes; ``load_component`` is how the CLI,
  the nodes, the launcher and the report get one.
- :mod:`.mesh_file`: volume meshes of the engineer's FE tool (meshio) and their node sets.
- :mod:`.mesh_examples`: volume meshes made here (a box, a tube, an L bracket) written in every
  format the mesh reader takes, for verification and benchmarks.
- :mod:`.mesh_component_file`: the ``component: mesh`` YAML, read into
  :class:`motoflex_ros.structures.mesh_component.MeshComponent`.
- :mod:`.superelement_file`: the ``component: superelement`` YAML and its Matrix Market files,
  read into :class:`motoflex_ros.structures.superelement_component.SuperelementComponent`, and
  the export of our own reductions in that form.
- :mod:`.design_space_file`: the design space of ``motoflex study design``, read into
  :class:`motoflex_ros.study.design_space.DesignSpace`, and the changed beam files it writes.

The numerical core (structures, vehicle, identify, bench, study) imports nothing from here: the
layer contract in pyproject.toml puts this package above them, and a forbidden contract says so
by name (docs/architecture.md). The core takes built objects (components, a PhysicalBench, a
DesignSpace); the layers above (cli, nodes, launcher, report) read the files with this package.
"""
