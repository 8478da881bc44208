"""Identification of lumped stiffness parameters (Passigato et al. 2023, Sect. 4.2).

- :mod:`.axis` eqs. (1)-(8): deformation axis (l, beta, b) and k from a pose of the loaded end.
- :mod:`.stiffness` eqs. (9)-(11): omega_n, zeta, J = k / omega_n^2, c = 2 zeta J omega_n;
  c = gamma k (gamma = 0.001 s) for the static models.
- :mod:`.decomposition` eqs. (12a)-(12b): k_t, k_b.
- :mod:`.peaks`: per-period sine fit of the harmonic tests, peak poses, running mean.
- :mod:`.decay`: omega_n, zeta from a free decay (matrix pencil).
- :mod:`.uncertainty`: linear propagation of the measurement scatter to 95 % intervals.
- :mod:`.identifier`: the streaming ``Identifier`` stage (load samples + measured poses in,
  readings out).
- :mod:`.results`: ``identify_component`` (readings -> static/torsion/bending models, k_t,
  k_b, sweep, modal data) and the JSON/YAML shape the vehicle side reads.
"""
