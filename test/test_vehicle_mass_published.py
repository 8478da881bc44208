"""Total mass, centre of mass and static wheel loads of the touring motorcycle (issue 5: "check
... the total mass and centre of mass").

Independent of the engine: masses and centres are read from the YAML file itself (bodies, their
parts, wheels at their centres) and summed here; the wheel loads follow from the moment balance
about the contact points, which lie below the wheel centres when upright (x_contact =
x_centre). Published: the laden (rider, no luggage) machines of docs/references.md ([SL01],
[MW94], [Cossalter]) put 41.1 % (Sharp-Limebeer 2001, Koenen's machine: 1250 N / 3042 N),
43.5 % (Sharp 1994: Z_f 1220 N / 2805 N) and 47.5 % (Cossalter sport-touring with rider:
b / p = 0.688 / 1.448) of the weight on the front wheel; no R 1200/1250 RT split is published
([RT])."""
import numpy as np
import pytest
import yaml

from motoflex_ros.config import config_path
from motoflex_ros.vehicle.lumped import mass_properties
from motoflex_ros.vehicle.model import _static_loads, vehicle_from_dict
from motoflex_ros.vehicle.tyre import tyre_from_config

LUGGAGE = ("side_case_left", "side_case_right", "top_case")
RIDER = ("rider_lower_body", "rider_upper_body")
PUBLISHED_FRONT_SHARE = {"Sharp-Limebeer 2001": 1250.0 / (1250.0 + 1792.0),
                         "Sharp 1994": 1220.0 / (1220.0 + 1585.0),
                         "Cossalter sport-touring": 0.688 / 1.448}


@pytest.fixture(scope="module")
def touring():
    with open(config_path("vehicles", "touring"), encoding="utf-8") as stream:
        data = yaml.safe_load(stream)
    return data, vehicle_from_dict(data, "touring")


def yaml_items(data, leave_out=()):
    """(name, mass [kg], position [m]) of every part, body and wheel, read from the YAML."""
    items = []
    for name, body in data["bodies"].items():
        for part, spec in body.get("parts", {name: body}).items():
            if part not in leave_out:
                items.append((part, float(spec["mass"]), np.array(spec["com"], float)))
    for name, wheel in data["wheels"].items():
        items.append((f"{name}_wheel", float(wheel["mass"]), np.array(wheel["centre"], float)))
    return items


def yaml_centre_of_mass(data, leave_out=()):
    items = yaml_items(data, leave_out)
    mass = sum(m for _, m, _ in items)
    return mass, sum(m * r for _, m, r in items) / mass


def moment_balance_loads(data, mass, com):
    """Front and rear wheel loads [N]: sum = m g, moment about each contact point zero."""
    weight = mass * data["gravity"]
    x_front, x_rear = (data["wheels"][w]["centre"][0] for w in ("front", "rear"))
    front = weight * (com[0] - x_rear) / (x_front - x_rear)
    rear = weight * (x_front - com[0]) / (x_front - x_rear)
    return front, rear


def test_touring_mass_and_com_equal_yaml_sum_roundtrip(touring):
    data, model = touring
    mass, com, inertia = mass_properties(model)
    want_mass, want_com = yaml_centre_of_mass(data)
    assert mass == pytest.approx(want_mass, rel=1e-12)
    assert model.total_mass() == pytest.approx(want_mass, rel=1e-12)
    np.testing.assert_allclose(com, want_com, rtol=0, atol=1e-12)
    # the file's own breakdown: 250 kg motorcycle + 88 kg rider + 40 kg luggage (masses are
    # given to 0.1 g: the bike's parts sum to 249.9999 kg)
    items = {name: m for name, m, _ in yaml_items(data)}
    assert sum(items[n] for n in RIDER) == pytest.approx(88.0, abs=5e-4)
    assert sum(items[n] for n in LUGGAGE) == pytest.approx(40.0, abs=5e-4)
    assert want_mass == pytest.approx(378.0, abs=5e-4)
    assert com[1] == pytest.approx(0.0, abs=1e-12)  # symmetric: c.o.m. in the mid-plane
    assert np.all(np.linalg.eigvalsh(inertia) > 0)


def test_touring_static_loads_moment_balance(touring):
    """The engine's loads are positive, sum to m g and are those of the moment balance; the
    engine's tyres are the Magic Formula linearized at the independently computed loads."""
    data, model = touring
    mass, com = yaml_centre_of_mass(data)
    front, rear = moment_balance_loads(data, mass, com)
    loads = _static_loads({b.name: b for b in model.bodies}, data["wheels"], data["gravity"])
    assert loads["front"] > 0 and loads["rear"] > 0
    assert loads["front"] + loads["rear"] == pytest.approx(mass * data["gravity"], rel=1e-12)
    assert loads["front"] == pytest.approx(front, rel=1e-12)
    assert loads["rear"] == pytest.approx(rear, rel=1e-12)
    for wheel in model.wheels:
        spec = data["wheels"][wheel.name]
        fz = front if wheel.name == "front" else rear
        want = tyre_from_config(spec["tyre"], "touring", "tyre", fz, spec["crown_radius"])
        for key in ("k_alpha", "k_gamma", "k_malpha", "k_mgamma"):
            assert getattr(wheel.tyre, key) == pytest.approx(getattr(want, key), rel=1e-12)


def test_touring_front_share_without_luggage_within_published_range(touring):
    """Rider aboard, luggage off: the front share lies within the published laden machines'
    41.1-47.5 %. (With the 40 kg of luggage behind the rear axle it drops to about 38 %, below
    them all: no published machine carries luggage.)"""
    data, _ = touring
    x_front = data["wheels"]["front"]["centre"][0]
    mass, com = yaml_centre_of_mass(data, leave_out=LUGGAGE)
    share = moment_balance_loads(data, mass, com)[0] / (mass * data["gravity"])
    assert min(PUBLISHED_FRONT_SHARE.values()) <= share <= max(PUBLISHED_FRONT_SHARE.values())
    laden_mass, laden_com = yaml_centre_of_mass(data)
    laden = laden_com[0] / x_front
    assert 0.35 < laden < share  # luggage behind the c.o.m. moves weight to the rear
