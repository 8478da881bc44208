"""The stiffness directions of the sensitivity pencil are those of A_0, and the pencil is checked.

pencil_study promises D_i = dA_0/dk_i, the derivative of the speed-independent coefficient of
A(v) = A_0 + v A_1 + v^2 A_2. Superposing D_i at every speed is right only if the springs do not
enter A_1 or A_2. References: (a) a synthetic pencil with a spring term made speed-dependent
(v^2 k), which the check must refuse, and the same pencil without it, which it must accept;
(b) the decomposed touring motorcycle: its directions equal differences of the A_0 of full
linearizations (quadratic fit over three speeds), and the superposed pencil equals a direct
linearization at the top speed.
"""
import numpy as np
import pytest

from motoflex_ros.errors import ModelError
from motoflex_ros.study.factorial import FACTORS, PAPER_TABLE2_NOMINAL
from motoflex_ros.study.tracked import pencil_study

NQ = 3
RNG = np.random.default_rng(5)
SPRINGS = RNG.standard_normal((len(FACTORS), NQ))


def coefficient(k, power, speed_dependent):
    """A_p of a 3-coordinate vehicle whose springs k_i s_i s_i^T / k_nom,i enter A_0 (and A_2
    for k_tf if ``speed_dependent``)."""
    a = np.zeros((2 * NQ, 2 * NQ))
    springs = sum(10.0 * k[f] / PAPER_TABLE2_NOMINAL[f] * np.outer(s, s)
                  for f, s in zip(FACTORS, SPRINGS))
    if power == 0:
        a[:NQ, NQ:] = np.eye(NQ)
        a[NQ:, :NQ], a[NQ:, NQ:] = -(springs + 20.0 * np.eye(NQ)), -0.3 * np.eye(NQ)
    elif power == 1:
        a[NQ:, NQ:] = -0.1 * np.ones((NQ, NQ))
    elif speed_dependent:
        a[NQ:, :NQ] = -1e-3 * k["k_tf"] / PAPER_TABLE2_NOMINAL["k_tf"] * np.eye(NQ)
    return a


@pytest.mark.parametrize("speed_dependent", [False, True])
def test_pencil_check_refuses_speed_dependent_springs_analytic(speed_dependent):
    nominal = dict(PAPER_TABLE2_NOMINAL)
    a_coeffs = np.stack([coefficient(nominal, p, speed_dependent) for p in range(3)])
    e_coeffs = np.stack([np.eye(2 * NQ), 0 * np.eye(2 * NQ), 0 * np.eye(2 * NQ)])

    def reference(k, v):
        return np.eye(2 * NQ), sum(v**p * coefficient(k, p, speed_dependent) for p in range(3))

    speeds = np.linspace(5.0, 50.0, 10)
    targets = np.linalg.eigvals(reference(nominal, speeds[0])[1])[:2]

    def build():
        return pencil_study(e_coeffs, a_coeffs, lambda k: coefficient(k, 0, speed_dependent),
                            nominal, speeds, targets, reference=reference)
    if speed_dependent:
        with pytest.raises(ModelError, match="differs from a direct linearization at 50 m/s"):
            build()
    else:
        assert build().state_matrices.directions.keys() == set(FACTORS)


@pytest.fixture(scope="module")
def motorcycle():
    from motoflex_ros.bench.offline_campaign import identify_components
    from motoflex_ros.config import config_path
    from motoflex_ros.formats.component_file import load_component, load_components
    from motoflex_ros.formats.json_yaml import to_jsonable
    from motoflex_ros.vehicle.lumped import COMPONENTS
    from motoflex_ros.vehicle.model import load_vehicle
    runs = identify_components(load_components(list(COMPONENTS)))
    identified = to_jsonable({n: r.identification.to_dict() for n, (_, r) in runs.items()})
    components = {name: load_component(name) for name in COMPONENTS}
    return load_vehicle(config_path("vehicles", "touring")), components, identified


def test_motorcycle_directions_are_those_of_A0_roundtrip(motorcycle):
    from motoflex_ros.study.identified_variants import build_variant
    from motoflex_ros.study.motorcycle import decomposed_study, with_stiffness
    from motoflex_ros.vehicle.linearize import linearize
    from motoflex_ros.vehicle.lumped import COMPONENTS
    vehicle, components, identified = motorcycle
    speeds = np.array([40.0, 125.0, 210.0]) / 3.6
    setup = decomposed_study(vehicle, components, identified, speeds)  # checks at 210 km/h
    directions = setup.study.state_matrices.directions

    def a0(values):
        model = build_variant(vehicle, "decomposed", list(COMPONENTS),
                              with_stiffness(identified, values), components)
        return linearize(model).A_coeffs[0]
    nominal = setup.nominal
    for factor in ("k_ta", "k_bs"):
        step = 0.1 * nominal[factor]
        expected = (a0({**nominal, factor: nominal[factor] + step}) - a0(nominal)) / step
        scale = np.abs(expected).max()
        assert scale > 0
        np.testing.assert_allclose(directions[factor], expected, rtol=0, atol=1e-7 * scale)
