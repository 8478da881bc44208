"""The paper's sensitivity findings (Sect. 5.3, Fig. 10) on our decomposed lumped motorcycle.

The study is the one ``motoflex study sensitivity`` runs: the shipped touring motorcycle, the
decomposed lumped model (a torsion and a bending joint per component), a 2^6 full factorial at
+/-10 % around the nominal stiffnesses, stability indices (eqs. 13-15) in 40-100 and
100-210 km/h, ANOVA and Pearson coefficients (eqs. 16-17). Both nominals of the CLI are
checked: "identified" (the bench identification, seed 0, the CLI default) and "table2" (the
paper's Table 2 stiffnesses on the identified axes, ``--nominal table2``). Each finding the paper
states is one test named for it; where ours differ the test is a strict expected failure whose
reason gives our numbers and the cause (the test of the cause is below them).

Conventions (the paper's): rho > 0 means a stiffer part damps the mode more. "Frame stiffness"
is checked three ways: the frame's torsion k_tf, its bending k_bf, and the whole frame (both up
together: rho with the coded sum x_tf + x_bf). In a balanced two-level design the factor columns
are orthogonal, so rho^2 is the share of an index's variance that factor explains; the
thresholds below use that:

* "barely moves" (swingarm on wobble): |rho| <= 0.1 |rho_max| of that index, i.e. the factor
  explains at most 1 % of what the dominant factor explains;
* "slightly hurts" (frame on high-speed wobble): rho < 0 and |rho| <= 0.5 |rho_max|, at most a
  quarter of the dominant factor's share (the paper: the front assembly has the strongest
  effect).

Speed grid: 10 km/h (the CLI allows at most 10). Every run's weave real part rises with speed,
and so does its wobble real part from 50 km/h on (16 identified runs dip by less than 0.01 1/s
between 40 and 50 km/h), so each index's s1 is the real part at the top of its range, a grid
point of every grid; the coarse grid is checked against the CLI's default 1 km/h grid below.
"""
from dataclasses import replace

import numpy as np
import pytest
from deviations import known_deviation

from motoflex_ros.cli.inputs import identification_results, motorcycle_components, study_speeds
from motoflex_ros.config import resolve_config
from motoflex_ros.study.correlation import pearson
from motoflex_ros.study.factorial import PAPER_TABLE2_NOMINAL
from motoflex_ros.study.motorcycle import decomposed_study, with_stiffness
from motoflex_ros.study.sensitivity import run_sensitivity
from motoflex_ros.units import kmh_to_ms
from motoflex_ros.vehicle.model import load_vehicle

NOMINALS = ("identified", "table2")
STEP_KMH, CLI_STEP_KMH = 10.0, 1.0
INDICES = ("weave_low", "weave_high", "wobble_low", "wobble_high")
BARELY, SLIGHTLY = 0.1, 0.5
FRAME = {"k_tf": ("k_tf",), "k_bf": ("k_bf",), "frame": ("k_tf", "k_bf")}

XFAIL = {
    # since issue 12's front assembly (compliance in the lower fork, the stanchion joint links
    # and the stanchions; the vehicle's lower-fork inertia) the identified nominal's k_ba and
    # k_tf curves cross at 100-101 km/h, just above the index's edge: there the paper's
    # low-speed direction holds, by a hair (rho +0.004 and +0.0009), and the marks apply to
    # the table2 nominal only (STUDY_MARKS)
    "k_ba": known_deviation(
        "low-speed-wobble-sign", "rho(wobble_low, k_ba) = -0.019 table2, cross at 98 km/h"),
    "k_bf": known_deviation(
        "low-speed-wobble-sign", "rho(wobble_low, k_bf) = -0.0017 / -0.0021, cross at 94-95 km/h"),
    # with the paper's load path (longitudinal arm on the rear frame, issue 12) the frame's
    # torsion joins them: its +/-10 % curves cross at 99 km/h (table2)
    "k_tf": known_deviation(
        "low-speed-wobble-sign", "rho(wobble_low, k_tf) = -0.0010 table2, cross at 99 km/h"),
    "frame": known_deviation(
        "low-speed-wobble-sign",
        "rho(wobble_low, k_tf + k_bf) = -0.0005 / -0.0022, cross at 99 km/h"),
}
XFAIL_ON = {"k_ba": ("table2",), "k_bf": NOMINALS, "k_tf": ("table2",), "frame": NOMINALS}
"""The nominals on which each expected failure holds."""


def _marked(factor, nominal):
    return (XFAIL[factor],) if nominal in XFAIL_ON.get(factor, ()) else ()


ON_BOTH = pytest.mark.parametrize("study", NOMINALS, indirect=True)


@pytest.fixture(scope="module")
def identified():
    """The CLI's default input: the bench identification of the three components (seed 0)."""
    return identification_results()


@pytest.fixture(scope="module")
def motorcycle():
    return load_vehicle(resolve_config("vehicles", "touring")), motorcycle_components()


_STUDIES = {}
"""The study of each nominal, computed once: pytest keeps one value of a module fixture at a
time and, with the nominal parametrized test by test (indirect, some with marks), it swapped
them back and forth, computing the two studies 13 times in all (about 15 s of CPU)."""


@pytest.fixture(scope="module")
def study(request, identified, motorcycle):
    """(setup, SensitivityResult, StudyRun) of one nominal on the 10 km/h grid."""
    if request.param not in _STUDIES:
        nominal = identified if request.param == "identified" else \
            with_stiffness(identified, PAPER_TABLE2_NOMINAL)
        speeds = study_speeds(STEP_KMH, STEP_KMH)
        setup = decomposed_study(*motorcycle, nominal, speeds)
        result, run = run_sensitivity(setup.study, setup.nominal, speeds, progress=False)
        _STUDIES[request.param] = setup, result, run
    return _STUDIES[request.param]


def rho(study, index, factors):
    """Pearson coefficient of ``index`` with the sum of the coded ``factors`` (eq. 16)."""
    _, result, run = study
    design = run.design
    columns = [design.factors.index(f) for f in factors]
    return float(pearson(design.coded[:, columns].sum(axis=1), result.indices[index].s)[0, 0])


def dominant(study, index):
    return max(abs(v) for v in study[1].pearson[index].values())


def table(study, index):
    return ", ".join(f"{f} {v:+.4f}" for f, v in study[1].pearson[index].items())


@ON_BOTH
@pytest.mark.parametrize("index", INDICES)
def test_main_effects_explain_95_percent_of_every_index(study, index):
    assert study[1].anova_main_share[index] >= 0.95


@ON_BOTH
def test_front_torsion_stiffness_destabilises_wobble_at_low_and_high_speed(study):
    for index in ("wobble_low", "wobble_high"):
        assert rho(study, index, ["k_ta"]) < 0, table(study, index)


@ON_BOTH
def test_front_bending_stiffness_stabilises_high_speed_weave(study):
    assert rho(study, "weave_high", ["k_ba"]) > 0, table(study, "weave_high")


@pytest.mark.parametrize("study", [pytest.param(n, marks=_marked("k_ba", n)) for n in NOMINALS],
                         indirect=True)
def test_front_bending_stiffness_stabilises_low_speed_wobble(study):
    assert rho(study, "wobble_low", ["k_ba"]) > 0, table(study, "wobble_low")


@ON_BOTH
def test_front_bending_stiffness_destabilises_high_speed_wobble(study):
    assert rho(study, "wobble_high", ["k_ba"]) < 0, table(study, "wobble_high")


@ON_BOTH
@pytest.mark.parametrize("frame", FRAME)
def test_stiffer_frame_helps_high_speed_weave(study, frame):
    assert rho(study, "weave_high", FRAME[frame]) > 0, table(study, "weave_high")


@pytest.mark.parametrize("study, frame", [pytest.param(n, f, marks=_marked(f, n))
                                          for n in NOMINALS for f in FRAME], indirect=["study"])
def test_stiffer_frame_helps_low_speed_wobble(study, frame):
    assert rho(study, "wobble_low", FRAME[frame]) > 0, table(study, "wobble_low")


@ON_BOTH
@pytest.mark.parametrize("frame", FRAME)
def test_stiffer_frame_slightly_hurts_high_speed_wobble(study, frame):
    value = rho(study, "wobble_high", FRAME[frame])
    assert -SLIGHTLY * dominant(study, "wobble_high") <= value < 0, table(study, "wobble_high")


@ON_BOTH
@pytest.mark.parametrize("index", ["wobble_low", "wobble_high"])
def test_swingarm_stiffness_barely_moves_wobble(study, index):
    for factor in ("k_ts", "k_bs"):
        assert abs(rho(study, index, [factor])) <= BARELY * dominant(study, index), \
            table(study, index)


@ON_BOTH
def test_lower_swingarm_bending_stiffness_helps_high_speed_weave(study):
    assert rho(study, "weave_high", ["k_bs"]) < 0, table(study, "weave_high")


@ON_BOTH
def test_lower_swingarm_bending_stiffness_hurts_low_speed_weave(study):
    assert rho(study, "weave_low", ["k_bs"]) > 0, table(study, "weave_low")


@ON_BOTH
def test_coarse_grid_coefficients_converge(study):
    """The 10 km/h grid gives the CLI default (1 km/h) grid's coefficients, signs included."""
    setup, coarse, _ = study
    fine_speeds = study_speeds(CLI_STEP_KMH, STEP_KMH)
    fine_study = replace(setup.study, speeds=tuple(fine_speeds))  # same pencil and start
    fine, _ = run_sensitivity(fine_study, setup.nominal, fine_speeds, progress=False)
    for index in INDICES:
        a, b = (np.array(list(r.pearson[index].values())) for r in (coarse, fine))
        np.testing.assert_array_equal(np.sign(a), np.sign(b))
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-9)
        assert coarse.anova_main_share[index] == pytest.approx(fine.anova_main_share[index],
                                                               abs=1e-9)


@ON_BOTH
def test_wobble_low_index_is_the_real_part_at_100_kmh(study):
    """Every run's wobble real part rises with speed from 50 km/h on, so s1 (eq. 13) over
    40-100 km/h is its value at 100 km/h (the first half of the expected failures' cause).
    Between 40 and 50 km/h 16 of the identified nominal's 64 runs dip by less than 0.01 1/s
    (issue 12's front assembly); table2's rise from 40 km/h."""
    _, result, run = study
    speeds = np.asarray(study[0].study.speeds)
    real = run.outputs["wobble"].real
    kmh = np.round(speeds * 3.6, 6)
    assert np.all(np.diff(real[:, kmh >= 50.0], axis=1) > 0)
    assert np.all(np.diff(real[:, kmh <= 50.0], axis=1) > -0.01)
    at_100 = real[:, np.argmin(abs(speeds - kmh_to_ms(100.0)))]
    np.testing.assert_allclose(result.indices["wobble_low"].s1, at_100, rtol=0, atol=1e-12)


def _one_at_a_time(study, factor):
    """Speeds [km/h] of the 1 km/h grid and Re(wobble) of +10 % minus -10 % ``factor``."""
    setup = study[0]
    speeds = study_speeds(CLI_STEP_KMH, STEP_KMH)
    values = {f: np.full(2, k) for f, k in setup.nominal.items()}
    values[factor] = setup.nominal[factor] * np.array([0.9, 1.1])
    wobble = replace(setup.study, speeds=tuple(speeds))(values)["wobble"].real
    return np.round(speeds * 3.6, 6), wobble[1] - wobble[0]  # [km/h], [1/s]


CROSSING_CASES = [(n, f) for f in ("k_ba", "k_bf", "k_tf") for n in NOMINALS
                  if n in XFAIL_ON[f]]


@pytest.mark.parametrize("study, factor", CROSSING_CASES, indirect=["study"])
def test_bending_effect_on_wobble_reverses_below_100_kmh(study, factor):
    """One factor at a time (+/-10 %, the others nominal, 1 km/h grid): the stiffer part has
    the lower wobble real part at 40 km/h and the higher one at 100 and 210 km/h; the curves
    cross once, between 80 and 100 km/h (the second half of the expected failures' cause)."""
    kmh, stiffer_minus_softer = _one_at_a_time(study, factor)
    at = {v: stiffer_minus_softer[kmh == v][0] for v in (40.0, 100.0, 210.0)}
    assert at[40.0] < 0 < at[100.0] and at[210.0] > 0, at
    crossings = kmh[:-1][np.diff(np.sign(stiffer_minus_softer)) != 0]
    assert len(crossings) == 1 and 80.0 <= crossings[0] < 100.0, crossings


@pytest.mark.parametrize("study, factor", [("identified", "k_ba"), ("identified", "k_tf")],
                         indirect=["study"])
def test_crossing_just_above_100_kmh_where_the_paper_holds(study, factor):
    """Where the paper's low-speed direction holds (identified k_ba, k_tf since issue 12's front
    assembly), it is because the +/-10 % curves cross once, just above 100 km/h (100-101):
    the stiffer part is the more stable one at 40 and 100 km/h, the less stable one at 210."""
    kmh, stiffer_minus_softer = _one_at_a_time(study, factor)
    at = {v: stiffer_minus_softer[kmh == v][0] for v in (40.0, 100.0, 210.0)}
    assert at[40.0] < 0 and at[100.0] < 0 < at[210.0], at
    crossings = kmh[:-1][np.diff(np.sign(stiffer_minus_softer)) != 0]
    assert len(crossings) == 1 and 100.0 <= crossings[0] < 110.0, crossings


@ON_BOTH
@pytest.mark.parametrize("factor", ["k_ba", "k_bf", "k_tf"])
def test_bending_stiffness_stabilises_wobble_below_the_crossing(study, factor):
    """Over the same 64 runs, indexed by -Re(wobble) at 40 or at 70 km/h or by minus its mean
    over the 40-100 km/h grid points (more damping, higher index, as eq. 15), the stiffer part
    is the more stable one: the paper's low-speed direction holds below the crossing."""
    _, _, run = study
    kmh = np.round(np.asarray(study[0].study.speeds) * 3.6, 6)
    real = run.outputs["wobble"].real
    column = run.design.factors.index(factor)
    for name, damping in (("40 km/h", -real[:, kmh == 40.0][:, 0]),
                          ("70 km/h", -real[:, kmh == 70.0][:, 0]),
                          ("mean 40-100 km/h", -real[:, kmh <= 100.0].mean(axis=1))):
        assert pearson(run.design.coded[:, column], damping)[0, 0] > 0, name
