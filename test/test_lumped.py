"""Lumped stiffness variants of the touring motorcycle (Passigato et al. 2023, Sect. 4.1, 5.1-5.2).

The identified parameters used here come straight from the clamped finite-element models (static
response, mode-shape axes, eq. 10 with the modal frequency), an independent path from the
time-domain bench, so these tests pin the vehicle side alone.
"""
import re
from dataclasses import replace

import numpy as np
import pytest
from hostile import run_motoflex

from motoflex_ros.config import config_path
from motoflex_ros.errors import ConfigError, ModelError
from motoflex_ros.formats.component_file import load_component
from motoflex_ros.identify.principal import principal_hinges
from motoflex_ros.lumped_stiffness.axis import axis_stiffness
from motoflex_ros.study import identified_variants
from motoflex_ros.study.identified_variants import build_variant, carried_by_component
from motoflex_ros.vehicle import lumped
from motoflex_ros.vehicle.linearize import linearize
from motoflex_ros.vehicle.model import load_vehicle
from motoflex_ros.vehicle.superelement import coordinate_names
from motoflex_ros.vehicle.variants import FLEX_CHOICES

SPEEDS = np.array([40.0, 120.0, 210.0]) / 3.6


@pytest.fixture(scope="module")
def vehicle():
    return load_vehicle(config_path("vehicles", "touring"))


@pytest.fixture(scope="module")
def components():
    out = {}
    for name in lumped.COMPONENTS:
        comp = load_component(name)
        out[name] = (comp, lumped.site_of(comp), comp.clamped_reduced())
    return out


def fe_identification(reduced):
    """l, beta, k, J, c as the bench would identify them, computed on the FE model directly."""
    static = reduced.static_lateral(100.0)
    result = {"static": {"l": static.axis.l, "beta": static.axis.beta, "k": static.k},
              "k_t": static.k, "k_b": static.k}
    y_static = static.end_motion[1]
    for label in ("torsion", "bending"):
        axis = reduced.mode_axis(label)
        omega = 2 * np.pi * reduced.frequency(label)
        k = axis_stiffness(static.force, y_static, axis.b)   # eq. (8) with this test's arm
        J = k / omega**2                                     # eq. (10)
        result[label] = {"l": axis.l, "beta": axis.beta, "k": k, "J": J,
                         "c": 2 * 0.01 * J * omega}          # eq. (11), zeta = 1 %
    return result


def fe_principal(reduced, carried):
    """The principal hinges of the FE model's end compliance (no bench) in the metric of what
    the loaded end carries in the vehicle."""
    c = np.column_stack([reduced.static_end_motion(w)[[1, 3, 5]] for w in np.eye(6)[[1, 3, 5]]])
    _, rows = principal_hinges(0.5 * (c + c.T), carried.metric(reduced.q0), reduced.q0)
    return {"identified": True, "hinges": [dict(zip(("l", "beta", "b", "k"), map(float, r)))
                                           for r in rows]}


@pytest.fixture(scope="module")
def identified(vehicle, components):
    carried = carried_by_component(vehicle, {n: comp for n, (comp, _, _) in components.items()})
    return {name: {**fe_identification(red), "principal": fe_principal(red, carried[name])}
            for name, (_, _, red) in components.items()}


def variant_model(vehicle, components, identified, variant, names, scale=1.0):
    """The variant through the public builder; ``scale`` multiplies every static stiffness."""
    if scale != 1.0:
        identified = {n: {**d, "static": {**d["static"], "k": d["static"]["k"] * scale}}
                      for n, d in identified.items()}
    models = {name: comp for name, (comp, _, _) in components.items()}
    return build_variant(vehicle, variant, names, identified, models)


@pytest.mark.parametrize("variant", FLEX_CHOICES)
def test_totals_equal_rigid_roundtrip(vehicle, components, identified, variant):
    """Total mass, centre of mass and inertia tensor stay those of the rigid motorcycle."""
    model = variant_model(vehicle, components, identified, variant, lumped.COMPONENTS)
    m0, c0, i0 = lumped.mass_properties(vehicle)
    m1, c1, i1 = lumped.mass_properties(model)
    assert abs(m1 - m0) <= 1e-9 * m0
    assert np.max(np.abs(c1 - c0)) <= 1e-9 * np.max(np.abs(c0))
    assert np.max(np.abs(i1 - i0)) <= 1e-9 * np.max(np.abs(i0))
    if variant == "flexible_bodies":   # the FE's springs and links replace four joints
        names = {j.name for j in model.joints}
        assert all(c in names for e in model.elements for c in coordinate_names(e))
        assert not names & {"stanchion_slide", "telelever_ball", "wheel_carrier_pivot",
                            "torque_strut_ball"}
        return
    if variant == "flexible":
        expected_joints = sum(se.n for se in model.elements)
    else:
        expected_joints = {"rigid": 0, "decomposed": 6, "principal": 5}.get(variant, 3)
    assert len(model.joints) - len(vehicle.joints) == expected_joints


def test_site_of_every_component_meets_the_vehicle(vehicle, components):
    for name, (_, site, _) in components.items():
        lumped.check_site(vehicle, name, site)


def test_misplaced_component_is_refused(vehicle, components):
    _, site, _ = components["front_assembly"]
    moved = replace(site, origin=site.origin + np.array([0.002, 0.0, 0.0]))
    with pytest.raises(ModelError, match="front_assembly.*2.0 mm from the front wheel centre"):
        lumped.check_site(vehicle, "front_assembly", moved)


def test_unknown_variant_and_missing_field_are_named(vehicle, components, identified):
    _, site, _ = components["frame"]
    with pytest.raises(ConfigError, match="'variant'.*not one of"):
        identified_variants.flex_joints("stiff", "frame", identified, site)
    partial = {"frame": {"static": {"l": 0.3, "beta": 2.0}}}
    with pytest.raises(ConfigError, match="'frame.static.k': missing"):
        identified_variants.flex_joints("static", "frame", partial, site)


def test_stiff_lumped_joints_converge_to_rigid_limit(vehicle, components, identified):
    """Scaling every lumped stiffness up makes the eigenvalues converge to the rigid ones."""
    rigid = linearize(vehicle)
    reference = [rigid.eigenvalues(v) for v in SPEEDS]
    errors = []
    for scale in (1e2, 1e4):
        model = variant_model(vehicle, components, identified, "static", lumped.COMPONENTS,
                              scale)
        lin = linearize(model)
        err = 0.0
        for v, ref in zip(SPEEDS, reference):
            values = lin.eigenvalues(v)
            # each rigid eigenvalue against the nearest one of the stiff model (the stiff model
            # has extra, fast hinge modes: -1/gamma on massless bodies, sqrt(k/J) otherwise)
            nearest = np.min(np.abs(values[None, :] - ref[:, None]), axis=1)
            err = max(err, np.max(nearest / np.maximum(np.abs(ref), 1.0)))
        errors.append(err)
    assert errors[1] < errors[0] / 10 and errors[1] < 1e-3


def test_eig_verb_with_flex_variant(identified, tmp_path):
    """``motoflex eig --flex`` builds the variant from a result file; its weave and wobble equal
    the core's sweep of the same variant."""
    import json

    from motoflex_ros.vehicle.modes import modal_sweep

    path = tmp_path / "identified.json"
    path.write_text(json.dumps(identified, default=float))
    result = run_motoflex(["eig", "--vehicle", "touring", "--speeds-ms", "20", "40", "--flex",
                           "static", "--component", "swingarm", "--identified", path, "--json"])
    assert result.returncode == 0, result.stderr
    out = json.loads(result.stdout)
    vehicle = load_vehicle(config_path("vehicles", "touring"))
    model = build_variant(vehicle, "static", ["swingarm"], identified,
                          {"swingarm": load_component("swingarm")})
    sweep = modal_sweep(linearize(model), np.array([20.0, 40.0]))
    for mode in ("weave", "wobble"):
        got = np.array([complex(*z) for z in out["modes"][mode]])
        assert np.allclose(got, sweep.modes[mode], rtol=1e-9)
    bad = run_motoflex(["eig", "--vehicle", "touring", "--speeds-ms", "20", "--flex", "static",
                        "--component", "fork"])
    assert bad.returncode == 2 and "unknown component 'fork'" in bad.stderr


def test_state_of_the_art_stiffness_analytic():
    """The literature's static tests on the shipped validation tube (along x, clamped at O):
    a moment about z at the tip gives k = E I / L; a lateral force F at the tip, about the axis
    through the clamp, gives eq. (8) with b = L and the Timoshenko tip deflection
    y = F L^3 / (3 E I) + F L / (kappa G A) (Cowper's kappa for a thin tube)."""
    tube = load_component("tube").clamped_reduced()
    length, d_out, wall, modulus, shear = 0.6, 0.04, 0.002, 2.1e11, 8.1e10
    d_in = d_out - 2 * wall
    inertia = np.pi / 64 * (d_out**4 - d_in**4)
    area = np.pi / 4 * (d_out**2 - d_in**2)
    nu, m2 = modulus / (2 * shear) - 1, (d_in / d_out) ** 2
    kappa = 6 * (1 + nu) * (1 + m2) ** 2 / ((7 + 6 * nu) * (1 + m2) ** 2 + (20 + 12 * nu) * m2)
    z_axis = np.array([0.0, 0.0, 1.0])
    moment_k = identified_variants.state_of_the_art_stiffness(tube, z_axis)
    assert moment_k == pytest.approx(modulus * inertia / length, rel=1e-6)
    y = length**3 / (3 * modulus * inertia) + length / (kappa * shear * area)
    force_k = identified_variants.state_of_the_art_stiffness(tube, z_axis, np.zeros(3),
                                                             "lateral_force")
    assert force_k == pytest.approx(length / np.arcsin(y / length), rel=1e-5)
    assert identified_variants.SOTA_LOAD["front_assembly"] == "lateral_force"   # Sect. 5.2.2


@pytest.mark.parametrize("value, problem", [(None, "finite number"), (float("nan"), "finite"),
                                            (-5.0, "out of the allowed range (> 0)"),
                                            ("stiff", "finite number")])
def test_bad_identified_stiffness_is_named(components, value, problem):
    _, site, _ = components["frame"]
    bad = {"frame": {"static": {"l": 0.3, "beta": 2.0, "k": value}}}
    with pytest.raises(ConfigError, match=r"'frame\.static\.k'.*" + re.escape(problem)):
        identified_variants.flex_joints("static", "frame", bad, site)
