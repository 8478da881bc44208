"""Table 2 of Passigato et al. (2023): k about the static axis and its split into k_t, k_b
(eq. 12), from the default bench campaign (5 um sensor noise, seed 0), within 10 %.

    Table 2 (N m/rad)      k          k_t        k_b
    Frame               1.03e6     3.75e5     3.59e6
    Front assembly      1.06e4     5.95e3     1.71e5
    Swingarm            1.33e5     1.04e6     1.39e5
"""
import functools

import pytest
from deviations import known_deviation

from motoflex_ros.bench.offline_campaign import run_campaign, setup_campaign
from motoflex_ros.formats.component_file import load_component

PAPER_TABLE2 = {"frame": {"k": 1.03e6, "k_t": 3.75e5, "k_b": 3.59e6},
                "front_assembly": {"k": 1.06e4, "k_t": 5.95e3, "k_b": 1.71e5},
                "swingarm": {"k": 1.33e5, "k_t": 1.04e6, "k_b": 1.39e5}}


@functools.cache
def identified(component):
    result = run_campaign(setup_campaign(load_component(component)), seed=0).identification
    return {"k": result.static["k"], **result.split.values}


@pytest.mark.parametrize("component", sorted(PAPER_TABLE2))
def test_table2_static_stiffness_published(component):
    assert identified(component)["k"] == pytest.approx(PAPER_TABLE2[component]["k"], rel=0.10)


AXES_DIFFER = known_deviation("table2-split-axes",
                              "k_t / k_b set by our static axes, 3-6 deg from the paper's")

FRONT_SPLIT = known_deviation("table2-front-assembly-kb",
                              "front assembly: k_b -48 % while k holds (eq. 12a)")


@pytest.mark.parametrize("component, key", [
    pytest.param("frame", "k_t", marks=AXES_DIFFER),
    pytest.param("frame", "k_b", marks=AXES_DIFFER),
    pytest.param("front_assembly", "k_t", marks=AXES_DIFFER),
    pytest.param("front_assembly", "k_b", marks=FRONT_SPLIT),
    pytest.param("swingarm", "k_t", marks=AXES_DIFFER),
    pytest.param("swingarm", "k_b", marks=AXES_DIFFER),
])
def test_table2_stiffness_split_published(component, key):
    assert identified(component)[key] == pytest.approx(PAPER_TABLE2[component][key], rel=0.10)
