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


@pytest.mark.parametrize("argv, key", [
    (["--speeds", "5", "0"], "--speeds"),
    (["--speeds", "-3"], "--speeds"),
    (["--range-kmh", "40", "210", "--step", "0"], "--step"),
    (["--range-kmh", "0", "20", "--step", "10"], "--range-kmh"),
])
def test_bad_speed_exits_nonzero(capsys, argv, key):
    code = main(["eig", "--vehicle", "whipple_benchmark", *argv])
    assert code == 2
    err = capsys.readouterr().err
    assert key in err and "> 0" in err


def test_bad_file_exits_nonzero(tmp_path, capsys, whipple):
    data = copy.deepcopy(whipple)
    data["bodies"]["rear_frame"]["inertia"]["zz"] = 30.0
    path = tmp_path / "broken.yaml"
    path.write_text(yaml.safe_dump(data))
    assert main(["eig", "--vehicle", str(path), "--speeds", "5"]) == 2
    err = capsys.readouterr().err
    assert "broken.yaml" in err and "bodies.rear_frame.inertia" in err
