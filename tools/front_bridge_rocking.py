#!/usr/bin/env python3
"""The per-body front assembly's bridge rocking and the joint links' tilt stiffness (issue 22).

Usage: python tools/front_bridge_rocking.py [--speeds-kmh 40 100 160 210]
                                            [--factors 1 3 10 30 100] [--part tilt|rotation]
                                            [--rocking-modes]

Prints, for the touring motorcycle with the front assembly flexible
(:mod:`motoflex_ros.study.tilt_stiffness`):
1. the fork bridge's rocking stiffness at the head when the head spring's rotations are freed
   (the Telelever's spherical head joint), at each factor;
2. with --rocking-modes, the oscillatory modes of the nominal per-body motorcycle between 2 and
   6 Hz at 100 km/h and the joint coordinate that moves most in each (one more linearization);
3. weave and wobble over speed for the one-clamped-superelement motorcycle, the per-body one
   with the head a revolute about the steering axis (the bridge held as on the bench) and the
   per-body one with the joint links' rotational stiffness times each factor; then, per factor,
   the least-damped real part of each mode over the speeds and where it is. --part tilt
   (default) scales the links' cardanic stiffness only, rotation their whole rotational block
   (the torsion about the stanchions too).
Minutes: one per-body linearization (about 85 s) per factor.
"""
import argparse
import sys

import numpy as np

from motoflex_ros.config import config_path
from motoflex_ros.formats.component_file import load_component
from motoflex_ros.study.identified_variants import build_variant
from motoflex_ros.study.tilt_stiffness import (
    FRONT,
    PARTS,
    TILT_FACTORS,
    bridge_rocking_stiffness,
    tilt_sweep,
)
from motoflex_ros.units import kmh_to_ms, ms_to_kmh
from motoflex_ros.vehicle.linearize import linearize
from motoflex_ros.vehicle.mode_names import STUDIED_MODES
from motoflex_ros.vehicle.model import load_vehicle


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


def _cells(values):
    return "  ".join(f"{z.real:+7.3f}{z.imag:+8.3f}j" for z in values)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--speeds-kmh", type=float, nargs="+", default=[40, 100, 160, 210])
    parser.add_argument("--factors", type=float, nargs="+", default=list(TILT_FACTORS))
    parser.add_argument("--part", choices=PARTS, default="tilt")
    parser.add_argument("--rocking-modes", action="store_true")
    args = parser.parse_args()
    speeds = kmh_to_ms(args.speeds_kmh)
    vehicle = load_vehicle(config_path("vehicles", "touring"))
    front = load_component(FRONT)
    print("1. fork bridge on the freed head, rocking stiffness [N m/rad] (steering, pitch/roll):")
    for factor in args.factors:
        stiffness = bridge_rocking_stiffness(front, factor, args.part)
        print(f"   joint links' {args.part} x {factor:<6g} {np.round(stiffness, 1)}")
    if args.rocking_modes:
        per_body = build_variant(vehicle, "flexible_bodies", [FRONT], {},
                                 {FRONT: front})
        print("2. per-body modes between 2 and 6 Hz at 100 km/h:",
              ", ".join(f"{f:.2f} Hz ({c})" for f, c in
                        rocking_modes(linearize(per_body), kmh_to_ms(100.0))))
    sweep = tilt_sweep(vehicle, front, speeds, args.factors, args.part,
                       progress=lambda label: print(f"   ... {label}", file=sys.stderr))
    print("3. weave and wobble [1/s] at "
          + ", ".join(f"{ms_to_kmh(v):g}" for v in speeds) + " km/h")
    for mode in STUDIED_MODES:
        print(f"   {'one clamped superelement':34s} {mode:6s} {_cells(sweep.superelement[mode])}")
        print(f"   {'per-body, head revolute':34s} {mode:6s} {_cells(sweep.held[mode])}")
        for factor, row in zip(sweep.factors, sweep.modes[mode]):
            label = f"per-body, links' {args.part} x {factor:g}"
            print(f"   {label:34s} {mode:6s} {_cells(row)}")
    print("   least damped over the speeds [1/s] (at km/h):")
    least = sweep.least_damped()
    for k, factor in enumerate(sweep.factors):
        print(f"   x {factor:<6g} " + "  ".join(
            f"{mode} {least[mode][0][k]:+.3f} ({ms_to_kmh(least[mode][1][k]):.0f})"
            for mode in STUDIED_MODES))


if __name__ == "__main__":
    main()
