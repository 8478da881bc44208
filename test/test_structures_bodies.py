"""The paper's flexible bodies (Appendix, Table A.1): each body of a component reduced by
Craig-Bampton on its own, the reduced bodies joined by the component's joints, against the
single (unreduced) FE model of the whole component (issue 12).

- Bodies: found from the model (elements hold a body together, joints join bodies); they are
  the paper's: the frame one body on the engine mounts; fork bridge, two stanchions, lower
  fork and longitudinal arm; lower link (main arm), upper link (torque strut), wheel carrier.
- Static: with every boundary DOF kept the constraint modes span the static response, so the
  loaded end's 6 x 6 compliance is the full model's to round-off (a property of Craig-Bampton,
  not a tolerance).
- Frequencies: Table 1's (first torsion, first bending) and every full-model mode below them
  within 0.5 %, and from above (the assembly is a Rayleigh-Ritz model of the full one).
"""
import numpy as np
import pytest
import scipy.sparse.linalg as spla

from motoflex_ros.config import MOTORCYCLE_COMPONENTS
from motoflex_ros.formats.component_file import load_component
from motoflex_ros.structures.bodies import assemble_bodies, reduce_bodies, split_bodies
from motoflex_ros.structures.full_model import full_clamped_matrices, full_clamped_modes

TOLERANCE = 5e-3   # the 0.5 %

# a node of each of the paper's bodies (Table A.1) and what the body is
PAPER_BODIES = {
    "frame": {"steering_head": "frame"},
    "front_assembly": {"fork_bridge": "fork bridge", "stanchion_top_left": "stanchion (left)",
                       "stanchion_top_right": "stanchion (right)",
                       "slider_top_left": "lower fork", "arm_pivot": "longitudinal arm"},
    "swingarm": {"swingarm_pivot": "lower link (main arm)", "strut_frame": "upper link "
                 "(torque strut)", "carrier_pivot": "wheel carrier"},
}


@pytest.fixture(scope="module", params=MOTORCYCLE_COMPONENTS)
def case(request):
    component = load_component(request.param)
    bodies = reduce_bodies(component)
    return component, bodies, assemble_bodies(component, bodies)


def test_bodies_are_the_papers(case):
    component, bodies, _ = case
    elastic = [b for b in bodies if b.fe_dofs > 6]
    names = component.node_names
    expected = PAPER_BODIES[component.name]
    assert len(elastic) == len(expected)
    body_of = {n: i for i, b in enumerate(elastic) for n in b.nodes}
    assert sorted(body_of[names[n]] for n in expected) == list(range(len(expected)))
    # what is not a body of the paper is a node held by springs alone (engine mounts, the
    # steering-head clamp): boundary only, no elasticity of its own
    for body in bodies:
        if body.fe_dofs == 6:
            assert len(body.nodes) == 1 and not np.any(body.K)


def test_split_keeps_every_node_once(case):
    component, bodies, _ = case
    nodes = sorted(n for b in split_bodies(component.structure) for n in b)
    assert nodes == list(range(len(component.node_xyz)))


def _full_static_compliance(component):
    k, _, asm = full_clamped_matrices(component)
    dofs = asm.node_dofs(component.loaded_end)
    rhs = np.zeros((k.shape[0], 6))
    rhs[dofs, np.arange(6)] = 1.0
    return spla.splu(k.tocsc()).solve(rhs)[dofs]


def test_static_loaded_end_response_is_the_single_models(case):
    component, _, assembly = case
    full = _full_static_compliance(component)
    joined = assembly.static_compliance(component.loaded_end)
    assert np.max(np.abs(joined - full)) <= 1e-9 * np.max(np.abs(full))


def test_table1_frequencies_within_half_a_percent_and_from_above(case):
    component, _, assembly = case
    full = full_clamped_modes(component, 12)
    joined = assembly.frequencies_hz()
    top = max(full.frequency("torsion"), full.frequency("bending"))
    below = full.frequencies_hz <= top * (1 + 1e-9)
    assert np.count_nonzero(below) >= 2
    ratio = joined[:len(full.frequencies_hz)][below] / full.frequencies_hz[below]
    assert np.all(ratio >= 1 - 1e-9)          # Rayleigh-Ritz: never below the full model
    assert np.all(ratio - 1 <= TOLERANCE), ratio


def test_bad_cross_body_link_refused():
    """A joint between two bodies is a spring or a spherical link (all three translations);
    a link of only some translations is refused, naming what is allowed."""
    from motoflex_ros.errors import ModelError
    from motoflex_ros.structures.bodies import _joints
    component = load_component("swingarm")
    structure = component.structure
    body_of = {n: i for i, b in enumerate(split_bodies(structure)) for n in b}
    master, slave, _ = structure.links[0]
    assert body_of[master] != body_of[slave]
    structure.links[0] = (master, slave, (0, 1))
    try:
        with pytest.raises(ModelError, match="translations only"):
            _joints(structure, body_of)
    finally:
        structure.links[0] = (master, slave, (0, 1, 2))


def test_cli_lists_the_bodies_as_table_a1():
    """``motoflex components --bodies --json``: the paper's body names (the files' ``bodies``
    key), FE DOFs, 'modes+boundary', and the assembly's Table 1 frequencies."""
    import json
    from contextlib import redirect_stdout
    from io import StringIO

    from motoflex_ros.cli.main import main
    out = StringIO()
    with redirect_stdout(out):
        assert main(["components", "--component", "front_assembly", "--bodies", "--json"]) == 0
    entry = json.loads(out.getvalue())["front_assembly"]
    names = [b["name"] for b in entry["bodies"]["list"]]
    assert sorted(names) == sorted(["fork_bridge", "stanchion_left", "stanchion_right",
                                    "lower_fork", "longitudinal_arm"])
    assert all(b["fe_dofs"] > 6 and "+" in b["reduced"] for b in entry["bodies"]["list"])
    assert entry["bodies"]["f_torsion_hz"] == pytest.approx(entry["f_torsion_full_hz"],
                                                            rel=TOLERANCE)


@pytest.mark.parametrize("bodies, message", [
    ("{arm: no_such_node}", "bodies.arm"),
    ("{a: slider_top_left, b: lower_bridge_left}", "name the same body"),
])
def test_bad_body_names_refused(tmp_path, bodies, message):
    from motoflex_ros.config import config_path
    from motoflex_ros.errors import MotoflexError
    text = config_path("components", "front_assembly").read_text()
    start = text.index("bodies: {")
    end = text.index("interfaces:")
    bad = tmp_path / "front.yaml"
    bad.write_text(text[:start] + f"bodies: {bodies}\n" + text[end:])
    with pytest.raises(MotoflexError, match=message) as err:
        reduce_bodies(load_component(str(bad)))
    assert "front.yaml" in str(err.value)
