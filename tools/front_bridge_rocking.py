#!/usr/bin/env python3
"""Why the per-body front assembly differs from the bench's (issue 12, docs/boundary-conditions.md).

Usage: python tools/front_bridge_rocking.py [--speeds-kmh 40 100 160 210]

Prints, for the touring motorcycle with the front assembly flexible:
1. the fork bridge's rotational stiffness at the head when the head spring's rotations are
   freed (the Telelever's spherical head joint), from the FE bodies joined in structures/;
2. the oscillatory modes of the per-body motorcycle between 2 and 6 Hz and the joint
   coordinate that moves most in each (the bridge rocking on the head joint: steer_2, steer_3);
3. weave and wobble over speed for: one clamped superelement (the bench's structure), the
   per-body motorcycle, the per-body motorcycle with the head a revolute about the steering
   axis (the bridge held as on the bench), and with the joint links' cardanic stiffness x 10
   and x 100.
"""
import argparse
from dataclasses import replace

import numpy as np

from motoflex_ros.config import config_path
from motoflex_ros.structures import load_component
from motoflex_ros.structures.bodies import assemble_bodies, reduce_bodies
from motoflex_ros.study.variants import build_variant
from motoflex_ros.vehicle.linearize import linearize
from motoflex_ros.vehicle.model import load_vehicle
from motoflex_ros.vehicle.modes import modal_sweep

NAME = "front_assembly"


def _spring_index(component, a, b):
    nodes = {component.node_names[a], component.node_names[b]}
    return next(i for i, (n1, n2, _) in enumerate(component.structure.springs)
                if {n1, n2} == nodes)


def bridge_stiffness_freed():
    """Eigenvalues [N m/rad] of the fork bridge's rotational stiffness at its head node with the
    head spring's rotations set to zero (translations kept)."""
    component = load_component(NAME)
    springs = component.structure.springs
    i = _spring_index(component, "steering_head", "fork_bridge")
    n1, n2, block = springs[i]
    freed = np.array(block, float)
    freed[3:, :] = 0.0
    freed[:, 3:] = 0.0
    springs[i] = (n1, n2, freed)
    joined = assemble_bodies(component, reduce_bodies(component))
    compliance = joined.static_compliance(component.node_names["fork_bridge"])[3:, 3:]
    return np.linalg.eigvalsh(np.linalg.inv(compliance))


def with_stiffer_joint_links(factor):
    """The front assembly with its joint links' rotational stiffness times ``factor``."""
    component = load_component(NAME)
    springs = component.structure.springs
    for top in ("left", "right"):
        i = _spring_index(component, f"fork_top_{top}", f"stanchion_top_{top}")
        n1, n2, block = springs[i]
        stiffer = np.array(block, float)
        stiffer[3:, 3:] *= factor
        springs[i] = (n1, n2, stiffer)
    return component


def rocking_modes(lin, speed):
    """(frequency [Hz], joint coordinate moving most) of the modes between 2 and 6 Hz."""
    values, vectors = np.linalg.eig(np.asarray(lin.state_matrix(np.array([speed])))[0])
    rates = [i for i, n in enumerate(lin.state_names) if n.endswith("_rate")]
    out = []
    for value, vector in zip(values, vectors.T):
        f = value.imag / (2 * np.pi)
        if value.imag > 0 and 2.0 < f < 6.0:
            share = np.abs(vector[rates]) ** 2
            out.append((f, lin.state_names[rates[int(np.argmax(share))]][:-5]))
    return sorted(out)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--speeds-kmh", type=float, nargs="+", default=[40, 100, 160, 210])
    speeds = np.asarray(parser.parse_args().speeds_kmh) / 3.6
    vehicle = load_vehicle(config_path("vehicles", "touring"))
    print("1. fork bridge at the head, head rotations freed: rotational stiffness eigenvalues "
          f"{np.round(bridge_stiffness_freed(), 1).tolist()} N m/rad")
    base = {NAME: load_component(NAME)}
    bodies = build_variant(vehicle, "flexible_bodies", [NAME], {}, base)
    held = replace(bodies, joints=tuple(replace(j, kind="revolute") if j.name == "steer"
                                        else j for j in bodies.joints))
    models = {"one clamped superelement": build_variant(vehicle, "flexible", [NAME], {}, base),
              "per-body": bodies, "per-body, head revolute": held}
    for factor in (10.0, 100.0):
        models[f"per-body, joint links x {factor:g}"] = build_variant(
            vehicle, "flexible_bodies", [NAME], {}, {NAME: with_stiffer_joint_links(factor)})
    print("2. per-body modes between 2 and 6 Hz at 100 km/h:",
          ", ".join(f"{f:.2f} Hz ({c})" for f, c in
                    rocking_modes(linearize(bodies), 100 / 3.6)))
    print("3. weave and wobble [1/s] at " + ", ".join(f"{v * 3.6:g}" for v in speeds) + " km/h")
    for label, model in models.items():
        sweep = modal_sweep(linearize(model), speeds)
        for mode in ("weave", "wobble"):
            cells = "  ".join(f"{z.real:+7.3f}{z.imag:+8.3f}j" for z in sweep.modes[mode])
            print(f"   {label:34s} {mode:6s} {cells}")


if __name__ == "__main__":
    main()
