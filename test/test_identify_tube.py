"""Closed form: a straight tube pitched in the x-z plane, lateral load at its free end.

The static bench test must give beta = pi/2 and the shear-deformable (Timoshenko) cantilever
values: tip deflection y = F L^3/(3 E I) + F L/(kappa G A), tip rotation theta = F L^2/(2 E I)
(shear does not rotate the end section), so the axis crosses the tube at l = L - y/theta =
L/3 - 2 E I/(kappa G A L), b = L - l, k = F b / asin(y / b). Euler-Bernoulli (kappa G A -> inf):
l = L/3, b = 2L/3, k = 4 E I/(3 L). kappa of a circular tube after Cowper (1966), J. Appl.
Mech. 33, 335-340.
"""
import numpy as np
import pytest
import yaml

from motoflex_ros.bench.offline_campaign import (
    only_tests,
    run_campaign,
    setup_campaign,
    with_sensor,
)
from motoflex_ros.formats.component_file import load_component
from motoflex_ros.identify.results import static_model

TUBE = {"length": 0.6, "outer_diameter": 0.04, "wall_thickness": 0.002}
MATERIAL = {"E": 2.1e11, "G": 8.1e10, "rho": 7850.0}


def timoshenko_cantilever(force):
    """(l, b, k) [m, m, N m/rad] of the lateral tip load on the tube (module docstring)."""
    length, d = TUBE["length"], TUBE["outer_diameter"]
    d_in = d - 2 * TUBE["wall_thickness"]
    area = np.pi / 4 * (d**2 - d_in**2)
    inertia = np.pi / 64 * (d**4 - d_in**4)
    nu = MATERIAL["E"] / (2 * MATERIAL["G"]) - 1
    m2 = (d_in / d) ** 2
    kappa = 6 * (1 + nu) * (1 + m2) ** 2 / ((7 + 6 * nu) * (1 + m2) ** 2 + (20 + 12 * nu) * m2)
    ei, kga = MATERIAL["E"] * inertia, kappa * MATERIAL["G"] * area
    y = force * length**3 / (3 * ei) + force * length / kga
    theta = force * length**2 / (2 * ei)
    b = y / theta
    return length - b, b, force * b / np.arcsin(y / b), 4 * ei / (3 * length)


def tube_file(tmp_path, pitch_deg):
    path = tmp_path / f"tube_{pitch_deg:+.0f}.yaml"
    path.write_text(yaml.safe_dump({"component": "tube", "tube": {**TUBE, "pitch_deg": pitch_deg},
                                    "material": MATERIAL, "elements": 20}))
    return str(path)


@pytest.mark.parametrize("pitch_deg", [0.0, 30.0, -45.0, 90.0, -80.0])
def test_tube_static_axis_analytic(tmp_path, pitch_deg):
    tube = load_component(tube_file(tmp_path, pitch_deg))
    setup = with_sensor(only_tests(setup_campaign(tube), ("static",)), noise_m=0.0,
                        resolution_m=0.0)
    run = run_campaign(setup)
    model, _ = static_model(run.readings["static"], setup.reduced.q0)
    l_ref, b_ref, k_ref, k_euler = timoshenko_cantilever(setup.protocol.static.force_n)
    assert model["beta"] == pytest.approx(np.pi / 2, abs=1e-6)
    assert model["l"] == pytest.approx(l_ref, rel=5e-3)
    assert model["b"] == pytest.approx(b_ref, rel=5e-3)
    assert model["k"] == pytest.approx(k_ref, rel=5e-3)
    # shear deformation matters here: it moves the axis away from the tip, k is 0.7 % above
    # the Euler-Bernoulli 4 E I / (3 L)
    assert abs(model["k"] / k_euler - 1) > 5e-3
