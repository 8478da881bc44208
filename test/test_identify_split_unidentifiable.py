"""Eq. (12) on a component whose lateral load does not excite one of its deformations.

A straight tube loaded sideways bends about an axis normal to it and hardly twists: the
'torsion' harmonic test (at the first torsion frequency) still finds an axis, but eq. (12)
then asks for a negative spring to rebuild the static deflection. Such a split is not
identifiable: the result says so with the reason (k_t, k_b NaN/null, split_identifiable False),
the CLI warns, and the consumers of k_t, k_b (the decomposed lumped variant, the sensitivity
study) refuse it with a ModelError naming the component. The independent check is eq. (12)
itself, solved directly (:func:`decompose_stiffness`) on the identified axes.
"""
import math

import pytest

from motoflex_ros.bench.offline_campaign import only_tests, run_campaign, setup_campaign
from motoflex_ros.cli.main import main
from motoflex_ros.errors import ModelError
from motoflex_ros.formats.component_file import load_component
from motoflex_ros.formats.json_yaml import to_jsonable
from motoflex_ros.identify.results import ResultsFile
from motoflex_ros.lumped_stiffness.decomposition import decompose_stiffness, split_problem
from motoflex_ros.study.factorial import PAPER_TABLE2_NOMINAL
from motoflex_ros.study.identified_variants import flex_joints
from motoflex_ros.study.motorcycle import nominal_stiffness, with_stiffness


@pytest.fixture(scope="module")
def tube():
    setup = only_tests(setup_campaign(load_component("tube")), ("static", "torsion", "bending"))
    return run_campaign(setup).identification


def test_split_problem_names_the_bad_value_analytic():
    assert split_problem(3.75e5, 3.59e6) is None
    assert "k_t = -2255" in split_problem(-2255.0, 1.6e4)
    assert "k_b = nan" in split_problem(1.0e4, math.nan)
    assert "k_t = 0" in split_problem(0.0, 1.0)


def test_tube_negative_k_t_is_not_identifiable(tube):
    s, t, b = tube.static, tube.torsion, tube.bending
    direct = decompose_stiffness(s["k"], s["beta"], s["b"], t["beta"], t["b"], b["beta"], b["b"])
    assert direct.k_t < 0 < direct.k_b            # eq. (12) has no two positive springs
    assert not tube.split_identifiable
    assert math.isnan(tube.split["k_t"]) and math.isnan(tube.split["k_b"])
    assert all(math.isnan(v) for v in tube.split.ci["k_t"] + tube.split.ci["k_b"])
    data = to_jsonable(tube.to_dict())
    assert data["k_t"] is None and data["k_b"] is None
    assert data["split_identifiable"] is False
    assert f"k_t = {direct.k_t:.4g} N m/rad" in data["split_problem"]


def test_identify_cli_warns_about_unidentifiable_split(capsys):
    assert main(["identify", "--component", "tube"]) == 0
    out = capsys.readouterr().out
    assert "warning: tube: k_t, k_b not identifiable: eq. (12) gives k_t = -" in out
    assert [line.split()[4] for line in out.splitlines() if "(eq. 12)" in line] == ["n/a"] * 2


def test_identification_status_warns(tube):
    from diagnostic_msgs.msg import DiagnosticStatus

    from motoflex_ros.nodes.result_messages import identification_statuses
    split = identification_statuses("tube", tube.to_dict())[0]
    assert split.name == "tube/split" and split.level == DiagnosticStatus.WARN
    assert "k_t = -" in split.message


def test_campaign_table_shows_na(tube, capsys):
    from motoflex_ros.cli.campaign_summary import stiffness_table
    stiffness_table({"frame": to_jsonable(tube.to_dict())}, {})
    rows = [line.split() for line in capsys.readouterr().out.splitlines()[2:]]
    assert [r[2] for r in rows if r[0] == "frame" and r[1] in ("k_t", "k_b")] == ["n/a", "n/a"]


def motorcycle_results(tube, unidentifiable):
    """Identify-format results of the three components: the tube's (flagged) split given to
    ``unidentifiable``, positive Table 2 values to the others (the check is about the flag)."""
    data = to_jsonable(tube.to_dict())
    out = {}
    for component in ("frame", "front_assembly", "swingarm"):
        out[component] = dict(data) if component == unidentifiable else {
            **data, "k_t": 1.0e5, "k_b": 1.0e5, "split_identifiable": True,
            "split_problem": None}
    return out


def test_decomposed_variant_refuses_unidentifiable_split(tube):
    identified = motorcycle_results(tube, "frame")
    with pytest.raises(ModelError, match=r"component 'frame'.*eq\. 12.*k_t = -"):
        flex_joints("decomposed", "frame", identified, site=None)
    # a result file without the flag, with a negative value, is refused the same way
    identified["frame"] = {**identified["frame"], "k_t": -2255.0, "k_b": 1.6e4}
    del identified["frame"]["split_identifiable"], identified["frame"]["split_problem"]
    with pytest.raises(ModelError, match=r"component .frame.*frame\.k_t = -2255"):
        flex_joints("decomposed", "frame", identified, site=None)


def test_sensitivity_study_refuses_unidentifiable_split(tube):
    identified = motorcycle_results(tube, "front_assembly")
    with pytest.raises(ModelError, match=r"component 'front_assembly'.*not identifiable"):
        nominal_stiffness(identified)
    # results read from a file: the message names the file
    with pytest.raises(ModelError, match=r"^run/id\.json: component 'front_assembly'"):
        nominal_stiffness(ResultsFile(identified, "run/id.json"))
    # stiffnesses given explicitly (the paper's Table 2) replace the identified split
    given = nominal_stiffness(with_stiffness(identified, PAPER_TABLE2_NOMINAL))
    assert given == PAPER_TABLE2_NOMINAL
