"""Invariance of the engine's eigenvalues to modelling choices that do not change the physics
(docs/vehicle-engine.md, the order of the checks): another root body, a reversed joint axis, a
body split into parts. Reference: the Meijaard et al. (2007) benchmark eigenvalues at 5 m/s."""
import copy

import numpy as np
import pytest
import yaml

from motoflex_ros.config import config_path
from motoflex_ros.vehicle.linearize import linearize
from motoflex_ros.vehicle.model import vehicle_from_dict

EIG_5_PUB = [-0.77534188219585 + 4.46486771378823j, -0.77534188219585 - 4.46486771378823j,
             -0.32286642900409, -14.07838969279820]


@pytest.fixture(scope="module")
def whipple():
    with open(config_path("vehicles", "whipple_benchmark"), encoding="utf-8") as stream:
        return yaml.safe_load(stream)


def _check(data):
    got = linearize(vehicle_from_dict(data, "variant")).eigenvalues(5.0)
    assert len(got) == 4
    for want in EIG_5_PUB:
        assert np.min(np.abs(got - want)) < 1e-9


def test_front_frame_as_root_published(whipple):
    data = copy.deepcopy(whipple)
    data["root"] = "front_frame"
    steer = data["joints"]["steer"]
    steer["parent"], steer["child"] = "front_frame", "rear_frame"
    _check(data)


def test_reversed_steer_axis_published(whipple):
    data = copy.deepcopy(whipple)
    data["joints"]["steer"]["axis"] = [-c for c in data["joints"]["steer"]["axis"]]
    _check(data)


def test_body_split_into_parts_published(whipple):
    """The rear frame as two parts whose combination is the published body."""
    data = copy.deepcopy(whipple)
    body = data["bodies"]["rear_frame"]
    # two halves of 42.5 kg at com +/- 0.1 m in x; parallel axis removes 85 * 0.1^2 from yy, zz
    half = {"mass": 42.5, "inertia": {"xx": 4.6, "yy": 5.5 - 0.425, "zz": 1.4 - 0.425,
                                      "xz": -1.2}}
    data["bodies"]["rear_frame"] = {"parts": {
        "front_half": dict(half, com=[body["com"][0] + 0.1, 0.0, body["com"][2]]),
        "rear_half": dict(half, com=[body["com"][0] - 0.1, 0.0, body["com"][2]])}}
    _check(data)


def test_reversed_wheel_axes_touring_roundtrip():
    """The sign of a wheel's spin axis in the file changes nothing (tyre side force, aligning
    and twisting moments included): the touring motorcycle with both axes reversed."""
    with open(config_path("vehicles", "touring"), encoding="utf-8") as stream:
        data = yaml.safe_load(stream)
    reference = linearize(vehicle_from_dict(copy.deepcopy(data), "touring")).eigenvalues(30.0)
    for wheel in data["wheels"].values():
        wheel["axis"] = [0.0, -1.0, 0.0]
    got = linearize(vehicle_from_dict(data, "reversed")).eigenvalues(30.0)
    assert len(got) == len(reference)
    assert max(np.min(np.abs(got - z)) for z in reference) < 1e-9 * np.max(np.abs(reference))
