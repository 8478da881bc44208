"""Table 2 of Passigato et al. (2023): k about the static axis and its split into k_t, k_b
(eq. 12), from the default bench campaign (5 um sensor noise, seed 0), within 10 %.

    Table 2 (N m/rad)      k          k_t        k_b
    Frame               1.03e6     3.75e5     3.59e6
    Front assembly      1.06e4     5.95e3     1.71e5
    Swingarm            1.33e5     1.04e6     1.39e5
"""
import functools

import pytest

from motoflex_ros.bench.offline_campaign import run_campaign, setup_campaign

PAPER_TABLE2 = {"frame": {"k": 1.03e6, "k_t": 3.75e5, "k_b": 3.59e6},
                "front_assembly": {"k": 1.06e4, "k_t": 5.95e3, "k_b": 1.71e5},
                "swingarm": {"k": 1.33e5, "k_t": 1.04e6, "k_b": 1.39e5}}


@functools.cache
def identified(component):
    result = run_campaign(setup_campaign(component), seed=0).identification
    return {"k": result.static["k"], **result.split.values}


@pytest.mark.parametrize("component", sorted(PAPER_TABLE2))
def test_table2_static_stiffness_published(component):
    assert identified(component)["k"] == pytest.approx(PAPER_TABLE2[component]["k"], rel=0.10)


AXES_DIFFER = pytest.mark.xfail(strict=True, reason=(
    "k_t / k_b follows from eq. (12b) and the axes alone, b_t sin(beta_t - beta) / (b_b "
    "sin(beta - beta_b)); the components are calibrated to Table 1 and k, not to the axes of "
    "Figs. 5-7, and their static axes lie 3-6 deg from where the paper's ratio needs them "
    "(frame +0.105 rad, front assembly +0.055 rad, swingarm -0.064 rad; issue 4 report; front "
    "assembly since issue 12's physical load path: k_t / k_b 0.048 against the paper's 0.035)"))

FRONT_SPLIT = pytest.mark.xfail(strict=True, reason=(
    "front assembly: k_b 8.9e4 against 1.71e5 N m/rad (-48 %; k_t 4.3e3 against 5.95e3, -28 %) "
    "while k holds (1.11e4 against 1.06e4): eq. 12a, b^2/k = b_t^2/k_t + b_b^2/k_b, with our "
    "axes (b 0.082, b_t 0.031, b_b 0.184 m) turns Table 2's k_t and k_b into k = 1.9e4, so the "
    "three cannot hold together on this geometry. Since issue 12 the compliance sits where a "
    "Telelever has it (lower fork, stanchion joint links, stanchions; no steering-head spring), "
    "calibrated to Table 1 and k; config/components/front_assembly.yaml"))


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
