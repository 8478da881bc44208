"""Bad vehicle input: clear ConfigError naming file and key, non-zero exit of ``motoflex eig``."""
import copy

import pytest
import yaml

from motoflex_ros.cli.main import main
from motoflex_ros.config import config_path
from motoflex_ros.errors import ConfigError
from motoflex_ros.vehicle.model import vehicle_from_dict


@pytest.fixture(scope="module")
def whipple():
    with open(config_path("vehicles", "whipple_benchmark"), encoding="utf-8") as stream:
        return yaml.safe_load(stream)


def _error(data, source="bad.yaml"):
    with pytest.raises(ConfigError) as info:
        vehicle_from_dict(data, source)
    return info.value


@pytest.mark.parametrize("inertia, words", [
    ({"xx": 1.0, "yy": 1.0, "zz": 1.0, "xz": 2.0}, "not positive definite"),
    ({"xx": 1.0, "yy": 1.0, "zz": 3.0}, "triangle inequality"),
])
def test_bad_inertia(whipple, inertia, words):
    data = copy.deepcopy(whipple)
    data["bodies"]["front_frame"]["inertia"] = inertia
    err = _error(data)
    assert err.key == "bodies.front_frame.inertia" and words in str(err)
    assert "bad.yaml" in str(err)


def test_bad_part_inertia(whipple):
    data = copy.deepcopy(whipple)
    body = data["bodies"].pop("rear_frame")
    data["bodies"]["rear_frame"] = {"parts": {"a": body, "b": dict(
        body, inertia={"xx": 1.0, "yy": 0.2, "zz": 0.2})}}
    assert _error(data).key == "bodies.rear_frame.parts.b.inertia"


def test_zero_length_axis(whipple):
    data = copy.deepcopy(whipple)
    data["joints"]["steer"]["axis"] = [0.0, 0.0, 0.0]
    err = _error(data)
    assert err.key == "joints.steer.axis" and "zero length" in str(err)


def test_crown_radius_above_radius(whipple):
    data = copy.deepcopy(whipple)
    data["wheels"]["front"]["crown_radius"] = 0.35
    err = _error(data)
    assert err.key == "wheels.front.crown_radius" and "below the wheel radius" in str(err)


def test_wheel_off_the_ground(whipple):
    from motoflex_ros.vehicle.dynamics import build_system

    data = copy.deepcopy(whipple)
    data["wheels"]["front"]["centre"] = [1.02, 0.0, 0.40]
    with pytest.raises(ConfigError) as info:
        build_system(vehicle_from_dict(data, "bad.yaml"))
    assert info.value.key == "wheels.front.centre"


def test_unknown_tyre_coefficient_missing(whipple):
    data = copy.deepcopy(whipple)
    data["wheels"]["rear"]["tyre"] = {"model": "magic_formula", "Fz0": 1000.0,
                                      "relaxation_a": 1e-5, "relaxation_b": 0.0,
                                      "relaxation_c": 0.0}
    assert _error(data).key.startswith("wheels.rear.tyre.")


@pytest.fixture(scope="module")
def touring():
    with open(config_path("vehicles", "touring"), encoding="utf-8") as stream:
        return yaml.safe_load(stream)


@pytest.mark.parametrize("name", ["pky8", "qbz3", "Pky1", "rby1"])
def test_unknown_magic_formula_coefficient(touring, name):
    """A misspelt or unmodelled coefficient (rby1: combined slip) was silently ignored."""
    data = copy.deepcopy(touring)
    data["wheels"]["front"]["tyre"][name] = 1.0
    err = _error(data)
    assert err.key == f"wheels.front.tyre.{name}" and "unknown key" in str(err)
    assert "pky1" in str(err)     # the allowed names are listed


@pytest.mark.parametrize("sibling, value", [("mass", 80.0), ("com", [0.5, 0.0, 0.6]),
                                            ("inertia", {"xx": 1.0, "yy": 1.0, "zz": 1.0})])
def test_parts_with_sibling_mass_properties(whipple, sibling, value):
    """A body given by parts ignored a sibling mass (or com, inertia): both is refused."""
    data = copy.deepcopy(whipple)
    body = data["bodies"].pop("rear_frame")
    data["bodies"]["rear_frame"] = {"parts": {"a": body}, sibling: value}
    err = _error(data)
    assert err.key == f"bodies.rear_frame.{sibling}" and "beside parts" in str(err)


@pytest.mark.parametrize("axis", [[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.01],
                                  [0.002, -1.0, 0.0]])
def test_wheel_axis_not_lateral(whipple, axis):
    """A wheel axis along x made the linearization fail (LinAlgError); any axis more than
    WHEEL_AXIS_TOLERANCE_RAD from +-y is not upright straight running."""
    data = copy.deepcopy(whipple)
    data["wheels"]["rear"]["axis"] = axis
    err = _error(data)
    assert err.key == "wheels.rear.axis" and "[0, 1, 0] or [0, -1, 0]" in str(err)


def test_wheel_axis_sign_is_free(whipple):
    data = copy.deepcopy(whipple)
    data["wheels"]["rear"]["axis"] = [0.0, -2.0, 0.0]
    wheel = vehicle_from_dict(data, "ok.yaml").wheels[0]
    assert wheel.name == "rear" and wheel.axis.tolist() == [0.0, 1.0, 0.0]


@pytest.mark.parametrize("argv, key", [
    (["--speeds-ms", "5", "0"], "--speeds"),
    (["--speeds-ms", "-3"], "--speeds"),
    (["--range-kmh", "40", "210", "--step-kmh", "0"], "--step"),
    (["--range-kmh", "0", "20", "--step-kmh", "10"], "--range-kmh"),
])
def test_bad_speed_exits_nonzero(capsys, argv, key):
    code = main(["eig", "--vehicle", "whipple_benchmark", *argv])
    assert code == 2
    err = capsys.readouterr().err
    assert key in err and "> 0" in err


@pytest.mark.parametrize("keys, value, key", [
    (("bodies", "rear_frame", "inertia", "zz"), 30.0, "bodies.rear_frame.inertia"),
    (("wheels", "front", "axis"), [1.0, 0.0, 0.0], "wheels.front.axis"),
])
def test_bad_file_exits_nonzero(tmp_path, capsys, whipple, keys, value, key):
    data = copy.deepcopy(whipple)
    node = data
    for name in keys[:-1]:
        node = node[name]
    node[keys[-1]] = value
    path = tmp_path / "broken.yaml"
    path.write_text(yaml.safe_dump(data))
    assert main(["eig", "--vehicle", str(path), "--speeds-ms", "5"]) == 2
    err = capsys.readouterr().err
    assert "broken.yaml" in err and key in err
