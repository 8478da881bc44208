"""Principal hinges (beyond the paper, identify/principal.py): closed forms, the bench's moment
tests, the rule, the reasons given where there are none."""
import json

import numpy as np
import pytest
import yaml

from motoflex_ros.bench.offline_campaign import (
    only_tests,
    run_campaign,
    setup_campaign,
    with_sensor,
)
from motoflex_ros.bench.plan import plan_campaign
from motoflex_ros.bench.protocols import load_protocol
from motoflex_ros.config import config_path, load_yaml
from motoflex_ros.errors import ConfigError, ModelError, ProtocolError
from motoflex_ros.formats.component_file import load_component
from motoflex_ros.identify.identifier import StaticReading
from motoflex_ros.identify.principal import (
    MOMENT_TESTS,
    PRINCIPAL_TESTS,
    CarriedInertia,
    hinge_compliance,
    identify_principal,
    unit_wrenches,
)
from motoflex_ros.identify.results import static_model
from motoflex_ros.study.identified_variants import check_principal

Q0 = np.array([0.45, 0.0, -0.30])          # a loaded end [m], component frame
AMPLITUDES = {"static": 200.0, "moment_axial": 30.0, "moment_normal": 80.0}


def readings_of(c, q0=Q0, scale=1.0, cov=1e-30):
    """Noise-free StaticReadings of the three tests on the compliance c (3 x 3): the pose's
    out-of-plane part C p, p the test's (F_y, M_x, M_z)."""
    out = {}
    for test, w in unit_wrenches(q0).items():
        amp = scale * AMPLITUDES[test]
        pose = np.zeros(6)
        pose[[1, 3, 5]] = c @ (amp * w[[1, 3, 5]])
        out[test] = StaticReading(amp, pose, np.eye(6) * cov, 400)
    return out


def hinge_vector(l, beta, q0=Q0):
    """The vector v = (b, cos phi, sin phi) of a hinge (eqs. 5-7)."""
    theta0 = np.arctan2(q0[2], q0[0])
    b = (np.hypot(q0[0], q0[2]) - l) * np.sin(beta)
    return np.array([b, np.cos(theta0 + beta), np.sin(theta0 + beta)])


def metric_making_orthogonal(vectors, masses):
    """A positive definite G with v_i^T G v_j = m_i delta_ij (G = B^-T diag(m) B^-1)."""
    inv = np.linalg.inv(np.column_stack(vectors))
    return inv.T @ np.diag(masses) @ inv


class FixedMetric(CarriedInertia):
    """A carried inertia given directly by its metric (for closed forms)."""

    def __new__(cls, g):
        obj = object.__new__(cls)
        object.__setattr__(obj, "g", np.asarray(g, float))
        return obj

    def __init__(self, g):
        pass

    def metric(self, q0):
        return self.g

    def to_dict(self):
        return {"metric": self.g.tolist()}


TWO_HINGES = [(0.12, 2.9, 5.0e3), (0.35, 1.4, 9.0e4)]  # (l [m], beta [rad], k [N m/rad])


def test_two_revolute_springs_in_series_come_back_exactly():
    """Two hinges in series with known axes: C = sum v v^T / k exactly, and in a metric that
    makes their modes the hinges (v1^T G v2 = 0, the carried body's modes are the hinges'
    own) both hinges come back to 1e-9 (noise-free)."""
    vs = [hinge_vector(l, beta) for l, beta, _ in TWO_HINGES]
    c = sum(hinge_compliance(k, l, beta, Q0) for l, beta, k in TWO_HINGES)
    np.testing.assert_allclose(c, sum(np.outer(v, v) / k for v, (_, _, k) in zip(vs, TWO_HINGES)),
                               rtol=1e-14)
    third = np.cross(vs[0], vs[1])
    g = metric_making_orthogonal([vs[0], vs[1], third], [3.0, 1.0, 2.0])
    result = identify_principal(readings_of(c), Q0, FixedMetric(g))
    assert result.identified, result.problem
    np.testing.assert_allclose(result.compliance, c, rtol=1e-12, atol=1e-12 * np.abs(c).max())
    assert len(result.hinges) == 2
    # lambda_i = m_i / k_i, largest first
    lam = sorted([3.0 / 5.0e3, 1.0 / 9.0e4], reverse=True)
    np.testing.assert_allclose(result.lam[:2], lam, rtol=1e-9)
    assert abs(result.lam[2]) < 1e-9 * lam[0]
    for hinge, (l, beta, k) in zip(result.hinges, TWO_HINGES):
        assert hinge["l"] == pytest.approx(l, abs=1e-9)
        assert hinge["beta"] == pytest.approx(beta, abs=1e-9)
        assert hinge["k"] == pytest.approx(k, rel=1e-9)
        assert hinge["c"] == pytest.approx(1e-3 * k, rel=1e-9)


def test_single_hinge_has_one_direction_equal_to_the_static_identification():
    """A single hinge: one significant direction in any metric, and it is the static test's
    hinge (eqs. 1-8 of the same F_y reading)."""
    l, beta, k = 0.2, 2.6, 2.0e4
    c = hinge_compliance(k, l, beta, Q0)
    carried = CarriedInertia(12.0, Q0 + [0.05, 0.0, -0.1], np.diag([0.4, 0.6, 0.3]))
    readings = readings_of(c, scale=1e-4)      # tiny rotations: eqs. 1-8 linear to 1e-7
    result = identify_principal(readings, Q0, carried)
    assert result.identified and len(result.hinges) == 1
    assert abs(result.lam[1]) < 1e-9 * result.lam[0]
    static = static_model(readings["static"], Q0)[0]
    hinge = result.hinges[0]
    for key, value in (("l", l), ("beta", beta), ("k", k)):
        assert hinge[key] == pytest.approx(value, rel=1e-9)
        assert static[key] == pytest.approx(hinge[key], rel=1e-6)


def test_frame_metric_reduces_to_the_static_test_on_the_bench():
    """The frame's head passes no moment: its metric has one direction and the principal
    hinge is the static test's (noise-free bench, the FE frame)."""
    setup = with_sensor(setup_campaign(load_component("frame"), noise_m=0.0), resolution_m=0.0)
    run = run_campaign(only_tests(setup, PRINCIPAL_TESTS))
    q0 = setup.reduced.q0
    carried = CarriedInertia(40.0, np.asarray(q0) + [0.2, 0.0, -0.4], np.eye(3), False)
    result = identify_principal(run.readings, q0, carried)
    static = static_model(run.readings["static"], q0)[0]
    assert result.identified and len(result.hinges) == 1
    hinge = result.hinges[0]
    # eqs. 1-8 read the finite rotation (1.4 mrad), C is linear: equal to that order
    assert hinge["k"] == pytest.approx(static["k"], rel=2e-3)
    assert hinge["beta"] == pytest.approx(static["beta"], abs=2e-3)
    assert hinge["l"] == pytest.approx(static["l"], abs=2e-3)


def test_bench_compliance_equals_the_reduced_model_and_intervals_cover_it():
    """Front assembly, default noise: C from the three holds against the reduced model's
    static compliance; every hinge's k interval covers the noise-free value."""
    setup = setup_campaign(load_component("front_assembly"))
    carried = CarriedInertia(20.08, np.asarray(setup.reduced.q0) + [0.02, 0.0, -0.05],
                             np.diag([0.9, 1.4, 0.5]))
    run = run_campaign(only_tests(setup, PRINCIPAL_TESTS))
    exact = np.column_stack([setup.reduced.static_end_motion(w)[[1, 3, 5]]
                             for w in np.eye(6)[[1, 3, 5]]])
    noisy = identify_principal(run.readings, setup.reduced.q0, carried)
    quiet = run_campaign(only_tests(with_sensor(setup, noise_m=0.0, resolution_m=0.0),
                                    PRINCIPAL_TESTS))
    clean = identify_principal(quiet.readings, setup.reduced.q0, carried)
    np.testing.assert_allclose(clean.compliance, 0.5 * (exact + exact.T), rtol=2e-3,
                               atol=2e-3 * np.abs(exact).max())
    assert noisy.info["reciprocity"] < 1e-2
    for h_noisy, h_clean in zip(noisy.hinges, clean.hinges):
        lo, hi = h_noisy.ci["k"]
        assert lo < h_clean["k"] < hi
        assert (hi - lo) / h_clean["k"] < 0.05


def test_no_moment_tests_is_reported_not_raised():
    """A protocol without 'moments' plans no moment test; the principal hinges are then not
    identified, with the reason, and the principal variant refuses by name."""
    protocol = load_protocol("default")
    assert protocol.moments is None
    readings = readings_of(np.eye(3) * 1e-5)
    result = identify_principal({"static": readings["static"]}, Q0, FixedMetric(np.eye(3)))
    assert not result.identified
    assert "moment_axial and moment_normal" in result.problem and "moments" in result.problem
    out = result.to_dict()
    assert out["identified"] is False and out["hinges"] == []
    with pytest.raises(ModelError, match="front_assembly.*principal hinges are not identified"
                                         ".*no moment_axial"):
        check_principal({"front_assembly": {"principal": out}}, "front_assembly")
    assert not identify_principal(readings, Q0, None).identified


def test_indefinite_compliance_gives_a_clear_message():
    """Noise larger than the stiffest direction's deflection: C indefinite, said so."""
    c = np.diag([1e-5, 2e-4, 1e-12])
    readings = readings_of(c)
    pose = readings["moment_normal"].pose.copy()
    pose[5] -= 1e-8                     # the stiff direction's reading lost in noise
    readings["moment_normal"] = StaticReading(readings["moment_normal"].force, pose,
                                              readings["moment_normal"].cov, 400)
    result = identify_principal(readings, Q0, FixedMetric(np.eye(3)))
    assert not result.identified
    assert "C is indefinite" in result.problem and "moments" in result.problem
    written = json.loads(json.dumps(result.to_dict()))   # what identify and the node write
    assert written["identified"] is False and written["problem"] == result.problem
    np.testing.assert_allclose(written["compliance"], result.compliance)


def test_moment_tests_are_planned_with_their_unit_moments():
    setup = setup_campaign(load_component("front_assembly"))
    by_name = {t.name: t for t in setup.plan.tests}
    q0 = setup.reduced.q0
    for name in MOMENT_TESTS:
        np.testing.assert_allclose(by_name[name].wrench, unit_wrenches(q0)[name])
        assert by_name[name].kind == "static"
        hold = setup.protocol.moments.hold_time_s
        assert by_name[name].max_samples == round((by_name["static"].ramp_time_s + hold)
                                                  * by_name["static"].rate_hz) + 1
    assert by_name["moment_axial"].amplitude_n == setup.protocol.moments.axial_nm
    assert setup.plan.load_limit_n == 1.5 * max(t.amplitude_n for t in setup.plan.tests
                                                if t.name not in MOMENT_TESTS)
    assert setup.plan.load_limit_nm == 1.5 * max(setup.protocol.moments.axial_nm,
                                                 setup.protocol.moments.normal_nm)


def _protocol_with(tmp_path, **moments):
    data = load_yaml(config_path("protocols", "front_assembly"))
    data["moments"].update(moments)
    path = tmp_path / "p.yaml"
    path.write_text(yaml.safe_dump(data))
    return path


def test_bad_moment_amplitude_names_file_and_key(tmp_path):
    path = _protocol_with(tmp_path, axial_nm=-5.0)
    with pytest.raises(ConfigError, match=r"p\.yaml.*moments\.axial_nm"):
        load_protocol(str(path))


def test_moment_beyond_the_linear_range_names_the_key(tmp_path):
    path = _protocol_with(tmp_path, normal_nm=1e5)
    setup = setup_campaign(load_component("front_assembly"))
    with pytest.raises(ProtocolError, match=r"p\.yaml: key 'moments\.normal_nm'.*N m turns"):
        plan_campaign(load_protocol(str(path)), setup.reduced, setup.modes)


def test_report_lists_the_principal_hinges_with_their_json_paths():
    """Issue 22: the report's identification table lists each identified hinge, its cells
    pointing at principal/hinges/<i> of the identification file."""
    from motoflex_ros.formats.json_yaml import to_jsonable
    from motoflex_ros.report.tables import identification_table
    vs = [hinge_vector(l, beta) for l, beta, _ in TWO_HINGES]
    c = sum(hinge_compliance(k, l, beta, Q0) for l, beta, k in TWO_HINGES)
    g = metric_making_orthogonal([vs[0], vs[1], np.cross(vs[0], vs[1])], [3.0, 1.0, 2.0])
    principal = identify_principal(readings_of(c, cov=1e-16), Q0, FixedMetric(g)).to_dict()
    model = {"l": 0.1, "beta": 1.0, "b": 0.05, "k": 1e4, "c": 10.0, "ci": {"k": [9e3, 1.1e4]}}
    identify = to_jsonable({name: {"static": model, "torsion": model, "bending": model,
                                   "principal": principal if name == "swingarm" else
                                   {"identified": False, "problem": "none", "hinges": []}}
                            for name in ("frame", "front_assembly", "swingarm")})
    table = identification_table(identify)
    labels = [(row[0].text, row[1].text) for row in table.rows]
    assert labels.count(("swingarm", "principal 1")) == labels.count(
        ("swingarm", "principal 2")) == 1
    assert not any(c == "frame" and t.startswith("principal") for c, t in labels)
    cells = {cell.path: cell for row in table.rows for cell in row if cell.path}
    for i, (_, beta, k) in enumerate(TWO_HINGES):
        assert cells[f"swingarm/principal/hinges/{i}/k"].value == pytest.approx(k, rel=1e-9)
        assert cells[f"swingarm/principal/hinges/{i}/beta"].value == pytest.approx(beta)
        assert cells[f"swingarm/principal/hinges/{i}/ci/k/0"].value < k


def test_principal_results_round_trip_through_diagnostic_key_values():
    """Issue 22: the identification node publishes the principal hinges as one
    DiagnosticStatus of KeyValues (WARN with the reason when not identified); read back they
    are the identification's numbers exactly."""
    pytest.importorskip("rclpy")
    from diagnostic_msgs.msg import DiagnosticStatus

    from motoflex_ros.formats.json_yaml import to_jsonable
    from motoflex_ros.nodes.result_messages import (
        identification_statuses,
        results_from_statuses,
    )
    vs = [hinge_vector(l, beta) for l, beta, _ in TWO_HINGES]
    c = sum(hinge_compliance(k, l, beta, Q0) for l, beta, k in TWO_HINGES)
    g = metric_making_orthogonal([vs[0], vs[1], np.cross(vs[0], vs[1])], [3.0, 1.0, 2.0])
    good = to_jsonable(identify_principal(readings_of(c, cov=1e-16), Q0,
                                          FixedMetric(g)).to_dict())
    missing = to_jsonable(identify_principal({}, Q0, None).to_dict())
    for principal in (good, missing):
        statuses = identification_statuses("swingarm", {"principal": principal})
        status = next(s for s in statuses if s.name == "swingarm/principal")
        back = results_from_statuses(statuses)["swingarm"]["principal"]
        assert back == principal
        if principal is missing:
            assert status.level == DiagnosticStatus.WARN and "moment_axial" in status.message
        else:
            assert status.level == DiagnosticStatus.OK


def test_tube_end_compliance_is_the_timoshenko_cantilever(tmp_path):
    """Closed form through the bench: the straight tube pitched 30 deg in x-z, the three tests
    noise-free. In the tube's own axes (u_y; theta along the tube e0; theta along n) the
    cantilever's compliance is [[L^3/3EI + L/kGA, 0, L^2/2EI], [0, L/GJ, 0], [L^2/2EI, 0,
    L/EI]] (J = 2 I the polar moment; F_y turns the tip about n = e0 x e_y)."""
    from test_identify_tube import MATERIAL, TUBE, timoshenko_cantilever, tube_file
    data = load_yaml(config_path("protocols", "default"))
    data["moments"] = {"axial_nm": 5.0, "normal_nm": 5.0}
    protocol = tmp_path / "with_moments.yaml"
    protocol.write_text(yaml.safe_dump(data))
    tube = load_component(tube_file(tmp_path, 30.0))
    setup = with_sensor(setup_campaign(tube, str(protocol)), noise_m=0.0, resolution_m=0.0)
    run = run_campaign(only_tests(setup, PRINCIPAL_TESTS))
    q0 = setup.reduced.q0
    result = identify_principal(run.readings, q0, FixedMetric(np.eye(3)))
    length, d = TUBE["length"], TUBE["outer_diameter"]
    d_in = d - 2 * TUBE["wall_thickness"]
    ei = MATERIAL["E"] * np.pi / 64 * (d**4 - d_in**4)
    gj = MATERIAL["G"] * np.pi / 32 * (d**4 - d_in**4)
    force = 1.0
    l_ref, b_ref, _, _ = timoshenko_cantilever(force)
    c_yy = b_ref * force * length**2 / (2 * ei)      # y = b theta (the Timoshenko deflection)
    local = np.array([[c_yy, 0.0, length**2 / (2 * ei)], [0.0, length / gj, 0.0],
                      [length**2 / (2 * ei), 0.0, length / ei]])
    e0, n = (unit_wrenches(q0)[t][3:] for t in MOMENT_TESTS)
    rotate = np.array([[1.0, 0.0, 0.0], [0.0, e0[0], e0[2]], [0.0, n[0], n[2]]])
    measured = rotate @ result.compliance @ rotate.T
    # measured 4e-7 of the largest entry (the FE beam is the Timoshenko cantilever)
    np.testing.assert_allclose(measured, local, rtol=1e-5, atol=1e-5 * np.abs(local).max())


@pytest.mark.parametrize("component, body_names, wheel_names", [
    ("front_assembly", ("lower_fork",), ("front",)),   # issue 22: lower fork plus front wheel
    ("swingarm", (), ("rear",)),                        # the rear wheel
])
def test_metric_is_the_carried_bodies_kinetic_energy_at_q0(component, body_names, wheel_names):
    """G, the metric of the principal hinges, against a second formulation: the kinetic energy
    of each carried body of the vehicle file, body by body, for the motions (u_y, theta_x,
    theta_z) of q0 (J^T diag(m, I) J summed; a sign slip in the offset terms moves the front
    assembly's bending hinge by 14 deg)."""
    from motoflex_ros.study.identified_variants import carried_by_component
    from motoflex_ros.vehicle import lumped
    from motoflex_ros.vehicle.model import load_vehicle

    vehicle = load_vehicle(config_path("vehicles", "touring"))
    bodies = {b.name: b for b in vehicle.bodies}
    wheels = {w.name: w for w in vehicle.wheels}
    parts = [(bodies[n].mass, bodies[n].com, bodies[n].inertia) for n in body_names]
    parts += [(wheels[n].mass, wheels[n].centre, wheels[n].inertia) for n in wheel_names]
    comp = load_component(component)
    q0 = np.asarray(comp.clamped_reduced().q0)
    q0_vehicle = q0 + lumped.site_of(comp).origin
    expected = np.zeros((3, 3))
    for mass, com, inertia in parts:
        r = np.asarray(com, float) - q0_vehicle
        jac = np.zeros((6, 3))
        jac[1, 0] = 1.0                                   # u_y: a lateral translation
        for j, axis in ((1, np.array([1.0, 0.0, 0.0])), (2, np.array([0.0, 0.0, 1.0]))):
            jac[:3, j] = np.cross(axis, r)                # theta about q0: the centre moves
            jac[3:, j] = axis
        inertia6 = np.zeros((6, 6))
        inertia6[:3, :3] = mass * np.eye(3)
        inertia6[3:, 3:] = inertia
        expected += jac.T @ inertia6 @ jac
    metric = carried_by_component(vehicle, {component: comp})[component].metric(q0)
    np.testing.assert_allclose(metric, expected, rtol=1e-12, atol=1e-12 * np.abs(expected).max())


def test_identify_takes_the_metric_from_the_vehicle_given(tmp_path, capsys):
    """`motoflex identify --vehicle FILE`: the swingarm's carried inertia (the rear wheel) is
    that vehicle's; a wheel twice as heavy doubles the carried mass and scales the metric G
    (G is linear in the masses and inertias: here the wheel alone)."""
    from motoflex_ros.cli.main import main

    data = load_yaml(config_path("vehicles", "touring"))
    data["wheels"]["rear"]["mass"] *= 2.0
    data["wheels"]["rear"]["inertia"] = {k: 2.0 * v
                                         for k, v in data["wheels"]["rear"]["inertia"].items()}
    heavy = tmp_path / "heavy.yaml"
    heavy.write_text(yaml.safe_dump(data))
    results = []
    for extra in ([], ["--vehicle", str(heavy)]):
        assert main(["identify", "--component", "swingarm", "--json", *extra]) == 0
        results.append(json.loads(capsys.readouterr().out)["swingarm"]["principal"])
    (base, twice) = results
    assert twice["carried"]["mass_kg"] == pytest.approx(2.0 * base["carried"]["mass_kg"])
    np.testing.assert_allclose(twice["metric"], 2.0 * np.asarray(base["metric"]), rtol=1e-12)
    # the hinge directions are the metric's eigen-directions: unchanged by a uniform scale
    for a, b in zip(base["hinges"], twice["hinges"]):
        assert a["k"] == pytest.approx(b["k"], rel=1e-9)
