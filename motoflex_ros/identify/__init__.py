"""Identification of lumped stiffness parameters (Passigato et al. 2023, Sect. 4.2).

- :mod:`motoflex_ros.lumped_stiffness` eqs. (1)-(8) and (12): the axis and the k_t, k_b split.
- :mod:`.stiffness` eqs. (9)-(11): omega_n, zeta, J = k / omega_n^2, c = 2 zeta J omega_n;
  c = gamma k (gamma = 0.001 s) for the static models.
- :mod:`.peaks`: per-period sine fit of the harmonic tests, peak poses, running mean.
- :mod:`.decay`: omega_n, zeta from a free decay (matrix pencil).
- :mod:`.uncertainty`: linear propagation of the measurement scatter to 95 % intervals.
- :mod:`.identifier`: the streaming ``Identifier`` stage (load samples + measured poses in,
  readings out).
- :mod:`.results`: ``identify_component`` (readings -> static/torsion/bending models, k_t,
  k_b, sweep, modal data) and the JSON/YAML shape the vehicle side reads.

- :mod:`.axis_model`: the identified model or axis: values, 95 % intervals, counts.
- :mod:`.matrix_pencil`: poles of a multi-channel free response.
- :mod:`.principal`: principal hinges in series from the out-of-plane end compliance.
- :mod:`.measurements`, :mod:`.physical_bench`, :mod:`.segmentation`, :mod:`.measured`: a
  real rig's load and marker streams, its bench (q0, markers, sensor; read from its bench file
  in :mod:`motoflex_ros.formats.bench_file`), the tests found in its load history, and their
  identification.
"""
