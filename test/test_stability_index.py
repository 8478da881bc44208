"""Stability index, eqs. (13)-(15), against values computed by hand on synthetic curves."""
import numpy as np
import pytest

from motoflex_ros.errors import ModelError
from motoflex_ros.study.stability_index import (
    crossing_speeds,
    max_real_part,
    speed_range,
    stability_index,
    stable_fraction,
)

GRID = np.arange(0.0, 10.5, 1.0)  # 0, 1, ..., 10 [m/s]
RANGE = (0.0, 10.0)

# name: (real part on GRID [1/s], s1, s2, s) worked out by hand
CASES = {
    # Re = -0.5 - 0.02 v: never crosses; s1 at v = 0; s2 = 1; s = 1 + 0.5
    "no_crossing": (-0.5 - 0.02 * GRID, -0.5, 1.0, 1.5),
    # Re = -1 + 0.25 v: crosses at v = 4; s1 = 1.5 at v = 10; stable [0, 4] -> 0.4
    "one_crossing": (-1.0 + 0.25 * GRID, 1.5, 0.4, 0.4),
    # Re = 0.75 - 0.5 |v - 5|: crossings 3.5 and 6.5 (between grid points); s1 = 0.75
    # stable [0, 3.5] and [6.5, 10] -> 7 / 10
    "two_crossings": (0.75 - 0.5 * np.abs(GRID - 5.0), 0.75, 0.7, 0.7),
    # Re = 0.2 + 0.01 v: unstable everywhere -> s2 = 0 and s = 0
    "always_unstable": (0.2 + 0.01 * GRID, 0.3, 0.0, 0.0),
    # Re = -0.1 |v - 5|: touches zero at v = 5 only -> s1 = 0, s2 = 1, s = 1
    "touching": (-0.1 * np.abs(GRID - 5.0), 0.0, 1.0, 1.0),
}


@pytest.mark.parametrize("name", list(CASES))
def test_index_analytic(name):
    re, s1, s2, s = CASES[name]
    index = stability_index(GRID, re[None, :], RANGE)
    np.testing.assert_allclose([index.s1[0], index.s2[0], index.s[0]], [s1, s2, s],
                               rtol=0, atol=1e-14)


def test_index_vectorised_over_runs_analytic():
    re = np.stack([case[0] for case in CASES.values()])
    index = stability_index(GRID, re, RANGE)
    expected = np.array([case[1:] for case in CASES.values()])
    np.testing.assert_allclose(np.column_stack([index.s1, index.s2, index.s]), expected,
                               atol=1e-14)


def test_index_three_crossings_analytic():
    # zig-zag through nodes 0..10: -1, 1, -1, -1, ..., crossings at 0.5, 1.5 and at 9.5
    re = np.array([-1.0, 1.0, -1.0, -1.0, -1.0, -1.0, -1.0, -1.0, -1.0, -1.0, 1.0])
    assert stable_fraction(GRID, re, RANGE) == pytest.approx((0.5 + 8.0) / 10.0, abs=1e-14)
    np.testing.assert_allclose(crossing_speeds(GRID, re), [0.5, 1.5, 9.5], atol=1e-14)


def test_index_range_off_grid_analytic():
    # one crossing at v = 4, range [0.5, 9.25] clipped between grid points
    re = -1.0 + 0.25 * GRID
    index = stability_index(GRID, re, (0.5, 9.25))
    assert index.s1[0] == pytest.approx(-1.0 + 0.25 * 9.25, abs=1e-14)
    assert index.s2[0] == pytest.approx((4.0 - 0.5) / 8.75, abs=1e-14)
    # never crossed inside [0.5, 3.5]: s1 is the interpolated end value
    inside = stability_index(GRID, re, (0.5, 3.5))
    assert inside.s1[0] == pytest.approx(-0.125, abs=1e-14)
    assert inside.s[0] == pytest.approx(1.125, abs=1e-14)


def test_index_paper_ranges_analytic():
    speeds = np.linspace(30.0, 220.0, 191) / 3.6  # 1 km/h grid [m/s]
    re = 0.01 * (speeds * 3.6 - 150.0)  # crosses at 150 km/h, rising
    low = stability_index(speeds, re, "low")
    high = stability_index(speeds, re, "high")
    assert low.s[0] == pytest.approx(1.0 + 0.5, abs=1e-12)  # s1 = -0.5 at 100 km/h
    assert high.s2[0] == pytest.approx(50.0 / 110.0, abs=1e-12)
    assert speed_range("high") == pytest.approx((100 / 3.6, 210 / 3.6))


def test_crossing_speed_converges():
    # Re = v^2 - 20 crosses at sqrt(20). The root of the linear interpolant errs by at most
    # max|f''| / (2 min|f'|) * h^2 / 4 on the cell holding the root (f' >= 2 sqrt(20) - 2h).
    for n in (11, 21, 41, 81, 161):
        v = np.linspace(0.0, 10.0, n)
        h = v[1] - v[0]
        error = abs(crossing_speeds(v, v**2 - 20.0)[0] - np.sqrt(20.0))
        bound = 2.0 / (2.0 * (2.0 * np.sqrt(20.0) - 2.0 * h)) * h**2 / 4.0
        assert 0 < error <= bound


def test_crossing_at_grid_point_counted_once():
    re = np.array([-1.0, 0.0, 1.0, 0.0, 0.0, -2.0])
    np.testing.assert_allclose(crossing_speeds(np.arange(6.0), re), [1.0, 3.0])


def test_max_real_part_ignores_speeds_outside_range():
    re = np.where(GRID > 8.0, 5.0, -1.0)  # unstable only above 8 m/s
    assert max_real_part(GRID, re, (0.0, 7.0))[0] == -1.0


@pytest.mark.parametrize("v_range", [(-1.0, 5.0), (2.0, 11.0), (5.0, 5.0)])
def test_range_outside_grid_is_an_error(v_range):
    with pytest.raises(ModelError, match="speed range"):
        stability_index(GRID, -np.ones_like(GRID), v_range)


def test_unknown_range_name_is_an_error():
    with pytest.raises(ModelError, match="allowed: low, high"):
        speed_range("medium")
