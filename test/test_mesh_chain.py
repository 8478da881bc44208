"""A solid mesh component through the whole chain (issue 15): ``motoflex components`` and
``motoflex identify`` (the bench campaign: static, harmonic, sweep, decay; eqs 1-12), their
--json output of the same shape as a beam component's, and the identified static k against the
finite-element model's own static compliance.

The component is an aluminium L bracket (motoflex_ros.formats.mesh_examples): a lateral
force at the foot of its leg bends and twists the arm, as on a single-sided swingarm, so the
torsion (318 Hz) and bending (87 Hz) tests and the split of eq. 12 all have something to find.
"""
import json

import numpy as np
import pytest
import scipy.sparse.linalg as spla
from hostile import run_motoflex
from regression import expected

from motoflex_ros.bench.offline_campaign import run_campaign, setup_campaign
from motoflex_ros.formats.component_file import load_component
from motoflex_ros.formats.mesh_examples import write_bracket_component
from motoflex_ros.lumped_stiffness.axis import axis_stiffness, deformation_axis
from motoflex_ros.structures.clamped import end_pose
from motoflex_ros.structures.full_model import full_clamped_matrices


def run_cli(*args):
    """The stdout of ``motoflex args`` run in this process (hostile.run_motoflex)."""
    result = run_motoflex(args)
    assert result.returncode == 0, result.stderr
    return result.stdout


@pytest.fixture(scope="module")
def bracket(tmp_path_factory):
    return str(write_bracket_component(tmp_path_factory.mktemp("bracket")))


def fe_static(path, force):
    """(l, beta, b, k) of the full clamped finite-element model under F_y at the loaded end:
    its own static compliance, no reduction, no bench (eqs 1-8)."""
    comp = load_component(path)
    k_c, _, asm = full_clamped_matrices(comp)
    f = np.zeros(k_c.shape[0])
    end = asm.node_dofs(comp.loaded_end)
    f[end[1]] = force
    motion = spla.spsolve(k_c.tocsc(), f)[end]
    q, rot = end_pose(motion, comp.q0)
    axis = deformation_axis(q, rot, comp.q0)
    return axis.l, axis.beta, axis.b, axis_stiffness(force, q[1], axis.b)


def keys(tree):
    """The nested key structure of a JSON document (list items by their first element); a
    number and null are one kind: JSON writes an undefined quantity (the straight tube's
    torsion axis has no joint on the line O-q0: l is null) as null."""
    if isinstance(tree, dict):
        return {k: keys(v) for k, v in tree.items()}
    if isinstance(tree, list):
        return [keys(tree[0])] if tree and isinstance(tree[0], (dict, list)) else "list"
    return "number" if isinstance(tree, (int, float)) or tree is None else type(tree).__name__


@pytest.mark.regression
def test_identify_json_end_to_end_against_fe_compliance(bracket):
    """``identify --json`` on the mesh component beside the beam tube: the same document shape;
    with an exact sensor the identified l, beta, b, k equal the FE model's static values to
    1e-3 (the bench reads a ramped load, not a static solve), and k_t, k_b are identified."""
    out = json.loads(run_cli("identify", "--component", bracket, "--component", "tube",
                             "--noise", "0", "--json"))
    assert set(out) == {"bracket", "tube"}
    mesh, beam = out["bracket"], out["tube"]
    # same shape: every key the beam's result has, the mesh's has too
    assert set(mesh) == set(beam)
    for test in ("static", "torsion", "bending"):
        assert keys(mesh[test]) == keys(beam[test]), test
    force = setup_campaign(load_component(bracket)).protocol.static.force_n
    l, beta, b, k = fe_static(bracket, force)
    static = mesh["static"]
    assert static["l"] == pytest.approx(l, rel=1e-3)
    assert static["beta"] == pytest.approx(beta, rel=1e-3)
    assert static["b"] == pytest.approx(b, rel=1e-3)
    assert static["k"] == pytest.approx(k, rel=1e-3)
    assert mesh["split_identifiable"] is True
    assert mesh["k_t"] > 0 and mesh["k_b"] > 0
    for label in ("torsion", "bending"):   # regression: test/regression_values.json
        assert mesh[label]["f_hz"] == expected(f"bracket.{label}_f_hz"), label


def test_identify_with_sensor_noise(bracket):
    """With the shipped 5 um sensor noise (seed 0) the identified k is within 1 % of the FE
    model's static stiffness and its 95 % interval holds it."""
    setup = setup_campaign(load_component(bracket))
    run = run_campaign(setup, seed=0)
    static = run.identification.to_dict()["static"]
    k = fe_static(bracket, setup.protocol.static.force_n)[3]
    assert static["k"] == pytest.approx(k, rel=0.01)
    low, high = static["ci"]["k"]
    assert low <= k <= high


def test_components_json_same_shape_as_beam(bracket):
    """``components --json``: the mesh component's entry has the beam tube's keys; its DOFs
    are the mesh's (spiders eliminated) and its reduced frequencies within 0.5 % of its full
    model's (no warning)."""
    out = json.loads(run_cli("components", "--component", bracket, "--component", "tube",
                             "--json"))
    mesh, beam = out["bracket"], out["tube"]
    assert set(mesh) == set(beam)
    for key in ("static_axis", "torsion_axis", "bending_axis", "frequency_model"):
        assert keys(mesh[key]) == keys(beam[key]), key
    assert mesh["dofs"] == load_component(bracket).dof_count()
    assert mesh["warnings"] == []
    for label in ("torsion", "bending"):
        assert mesh[f"f_{label}_hz"] == pytest.approx(mesh[f"f_{label}_full_hz"], rel=0.005)
