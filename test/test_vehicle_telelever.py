"""The touring motorcycle as the paper's mechanisms (issue 12, Sect. 4.1 of the paper).

With every suspension coordinate locked and everything rigid, the Telelever (head spherical
joint, stanchion slide, lower spherical joint, longitudinal arm) and the Paralever four-bar are
kinematically one revolute steering joint about the axis through the two spherical joints and
a swingarm welded to the frame. So the mechanism motorcycle must give the eigenvalues of a
tree motorcycle built here from the same file with that revolute steering joint and fixed
joints in place of the loops, to 1e-6.
"""
import copy

import numpy as np
import pytest
import yaml

from motoflex_ros.config import config_path
from motoflex_ros.vehicle.dynamics import build_system
from motoflex_ros.vehicle.linearize import linearize
from motoflex_ros.vehicle.model import vehicle_from_dict

SPEEDS = (5.0, 15.0, 30.0, 45.0, 58.0)


def _touring():
    with open(config_path("vehicles", "touring")) as stream:
        return yaml.safe_load(stream)


def _revolute_equivalent(data):
    """The same bodies on a tree: revolute steering joint, everything else welded."""
    data = copy.deepcopy(data)
    joints = data["joints"]
    steer = joints["steer"]
    joints["steer"] = {"type": "revolute", "parent": steer["parent"], "child": steer["child"],
                       "axis": steer["axis"], "point": steer["point"],
                       "damping": steer["damping"]}
    for name in ("stanchion_slide", "telelever_arm_pivot", "swingarm_pivot",
                 "torque_strut_mount", "wheel_carrier_pivot"):
        joints[name] = {"type": "fixed", "parent": joints[name]["parent"],
                        "child": joints[name]["child"]}
    for name in ("telelever_ball", "torque_strut_ball"):
        del joints[name]
    return data


def _matched(a, b):
    """Largest relative distance between two eigenvalue sets, matched one to one."""
    from scipy.optimize import linear_sum_assignment
    cost = np.abs(a[:, None] - b[None, :])
    rows, cols = linear_sum_assignment(cost)
    return float(np.max(cost[rows, cols] / np.maximum(np.abs(b[cols]), 1.0)))


def test_touring_is_a_mechanism_with_the_paper_s_load_paths():
    system = build_system(vehicle_from_dict(_touring()))
    cuts = sorted(c.joint.name for c in system.tree.cut_joints)
    assert cuts == ["telelever_ball", "torque_strut_ball"]
    locked = sorted(c.name for c in system.tree.coordinates if c.locked)
    assert locked == ["stanchion_slide", "swingarm_pivot"]
    # the frozen mechanism leaves the rider's lean and the steering angle, as the revolute bike
    names = [system.tree.coordinates[k].name for k in system.indep_pos]
    assert names == ["roll", "rider_lean", "steer"]
    # the longitudinal arm hangs from the rear frame, not from the steering head
    arm = next(j for j in system.model.joints if j.name == "telelever_arm_pivot")
    assert arm.parent == "frame"


@pytest.mark.parametrize("speed", SPEEDS)
def test_rigid_mechanism_equals_revolute_steering_motorcycle_roundtrip(speed):
    data = _touring()
    mechanism = linearize(vehicle_from_dict(data, "touring.yaml"))
    tree = linearize(vehicle_from_dict(_revolute_equivalent(data), "touring-tree"))
    assert _matched(mechanism.eigenvalues(speed), tree.eigenvalues(speed)) < 1e-6


def test_a_steering_axis_off_the_lower_joint_is_not_a_revolute_any_more():
    """Move the lower spherical joint 5 mm off the rake line: the fork then turns about the
    line through the two spherical joints, not the file's steering axis, and the equivalence
    breaks (the test above can fail)."""
    data = _touring()
    data["joints"]["telelever_ball"]["point"] = [1.3875, 0.0, 0.450]
    mechanism = linearize(vehicle_from_dict(data, "touring.yaml"))
    tree = linearize(vehicle_from_dict(_revolute_equivalent(_touring()), "touring-tree"))
    assert _matched(mechanism.eigenvalues(30.0), tree.eigenvalues(30.0)) > 1e-4
