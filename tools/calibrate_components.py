#!/usr/bin/env python3
"""Calibrate a component YAML against the paper's Table 1 and Table 2 (a design aid, not a test).

Usage: python tools/calibrate_components.py COMPONENT PARAM [PARAM ...] [--weights W]
PARAM is a dotted path into the YAML (e.g. sections.spar.outer_diameter,
springs.0.k_rotation.2, rigid_parts.tank_left.mass), optionally with '@F' to bound its factor
to [1/F, F]; paths joined by ',' share one factor; a path ending in '*' scales every numeric
leaf below it together (e.g. 'sections.spar.*' scales diameter and wall: a geometric scale).
The fit minimises log-ratios of (f_torsion, f_bending, k, k_t, k_b) to the paper and penalises
a first clamped mode that is not of the paper's type. It prints the fitted values; copying them
into the YAML (with a comment saying what was fitted) is done by hand.

--match-body PART=BODY:SECTION[,SECTION...] keeps a group of the component equal to a rigid body
of the vehicle (--vehicle, default touring) while the fit changes its members: before every
evaluation the rigid part PART is reset so that the members of those sections plus every rigid
part on their nodes have BODY's mass, centre of mass and inertia (e.g. the front assembly's
lower fork: lower_fork_casting=lower_fork:slider,lower_bridge,axle). A rigid part's inertia is
diagonal in the component axes: the products the members leave are folded into I_zz about the
vehicle's steering axis (role steer), so the inertia about that axis is exact.
"""
import argparse
import copy
import sys

import numpy as np
from scipy.optimize import least_squares

from motoflex_ros.config import load_yaml, resolve_config, validate
from motoflex_ros.structures.assembly import Structure, rigid_body_mass, rigid_field
from motoflex_ros.structures.component_model import Component
from motoflex_ros.structures.component_schema import (
    STRUCTURE_SCHEMA,
    _add_members,
    structure_from_config,
)
from motoflex_ros.structures.component_summary import summarize
from motoflex_ros.structures.paper_tables import (
    paper_table1_eigenfrequencies,
    paper_table2_stiffness,
)
from motoflex_ros.vehicle.model import load_vehicle

FIRST_MODE = {"frame": "torsion", "front_assembly": "torsion", "swingarm": "bending"}


def _get(data, path):
    node = data
    for key in path.split("."):
        node = node[int(key)] if isinstance(node, list) else node[key]
    return node


def _get_parent(data, path):
    keys = path.split(".")
    node = data
    for key in keys[:-1]:
        node = node[int(key)] if isinstance(node, list) else node[key]
    last = keys[-1]
    return node, (int(last) if isinstance(node, list) else last)


def _scale_all(node, factor):
    for key in list(node.keys() if isinstance(node, dict) else range(len(node))):
        value = node[key]
        if isinstance(value, (int, float)) and not isinstance(value, bool):
            node[key] = value * factor
        elif isinstance(value, (dict, list)):
            _scale_all(value, factor)


def apply(data, params, factors):
    out = copy.deepcopy(data)
    pairs = [(p, f) for group, f in zip(params, factors) for p in group.split(",")]
    for path, factor in pairs:
        if path.endswith(".*"):
            _scale_all(_get(out, path[:-2]), factor)
        else:
            parent, key = _get_parent(out, path)
            parent[key] = parent[key] * factor
    return out


def group_mass(data, sections, skip=()):
    """Mass [kg], centre of mass [m] and inertia about it [kg m^2] (component frame) of the
    members of ``sections`` and the rigid parts on their nodes (parts named in ``skip`` left
    out); the consistent beam mass matrices, rigid motion of the group's nodes."""
    cfg = validate(copy.deepcopy(data), STRUCTURE_SCHEMA, "calibration")
    cfg["members"] = [m for m in cfg["members"] if m["section"] in sections]
    held = {m[end] for m in cfg["members"] for end in ("from", "to")}
    s = Structure()
    names = {n: s.add_node(xyz) for n, xyz in cfg["nodes"].items()}
    _add_members(s, cfg, names, "calibration")
    asm = s.assemble()
    gamma = rigid_field(s.xyz)
    rigid = gamma.T @ (asm.expand @ asm.M @ asm.expand.T).toarray() @ gamma
    for part_name, part in cfg["rigid_parts"].items():
        if part["node"] in held and part_name not in skip:
            node = np.asarray(cfg["nodes"][part["node"]], float)
            block = rigid_body_mass(part["mass"], np.diag(part["inertia"]),
                                    np.asarray(part["cg"], float) - node)
            g = rigid_field(node[None, :])
            rigid += g.T @ block @ g
    mass = rigid[3, 3]
    cross = -rigid[3:, :3] / mass              # [c]x: node velocity v0 - [r]x omega
    cg = np.array([cross[2, 1], cross[0, 2], cross[1, 0]])
    return mass, cg, rigid[:3, :3] - mass * (cg @ cg * np.eye(3) - np.outer(cg, cg))


def _about(mass, cg, inertia, point):
    r = cg - point
    return inertia + mass * (r @ r * np.eye(3) - np.outer(r, r))


def match_body(data, spec, vehicle):
    """``data`` with rigid part PART reset as --match-body PART=BODY:SECTIONS says."""
    part_name, rest = spec.split("=")
    body_name, sections = rest.split(":")
    body = next(b for b in vehicle.bodies if b.name == body_name)
    steer = next(j for j in vehicle.joints if j.name == vehicle.roles.get("steer", "steer"))
    out = copy.deepcopy(data)
    origin = np.asarray(out["placement"]["origin"], float)
    mass, cg, inertia = group_mass(out, set(sections.split(",")), skip=(part_name,))
    m_p = body.mass - mass
    c_body = np.asarray(body.com, float) - origin
    c_p = (body.mass * c_body - mass * cg) / m_p
    tensor = _about(body.mass, c_body, body.inertia, c_p) - _about(mass, cg, inertia, c_p)
    a = np.asarray(steer.axis, float) / np.linalg.norm(steer.axis)
    diag = np.diag(tensor).copy()
    diag[2] = (a @ tensor @ a - a[0] ** 2 * diag[0] - a[1] ** 2 * diag[1]) / a[2] ** 2
    part = out["rigid_parts"][part_name]
    part.update(mass=float(m_p), cg=[float(x) for x in c_p], inertia=[float(x) for x in diag])
    return out


def evaluate(name, data):
    cfg = validate(data, STRUCTURE_SCHEMA, "calibration")
    comp = structure_from_config(cfg, "calibration", Component)
    red = comp.clamped_reduced()
    return summarize(comp, red), red


def residuals(name, data, weights):
    t1, t2 = paper_table1_eigenfrequencies()[name], paper_table2_stiffness()[name]
    s, red = evaluate(name, data)
    values = [s.f_torsion_hz / t1["torsion"], s.f_bending_hz / t1["bending"],
              s.k_static / t2["k"], s.k_t / t2["k_t"], s.k_b / t2["k_b"]]
    res = [w * (np.log(v) if np.isfinite(v) and v > 0 else 5.0)
           for v, w in zip(values, weights[:5])]
    # Sect. 5.1 (Figs. 5-7): torsion axis nearly parallel to O-q0, bending axis nearly
    # perpendicular to it; weights[5] pulls the mode axes towards that (0 = off)
    axis_weight = weights[5] if len(weights) > 5 else 0.0
    for ax, target in ((s.torsion_axis, 0.0), (s.bending_axis, np.pi / 2)):
        if ax is None:
            res.append(5.0 * axis_weight)
            continue
        off = abs(np.angle(np.exp(2j * (ax.beta - target)))) / 2   # distance modulo pi
        res.append(axis_weight * off / (np.pi / 4))
    first = red.frequency(FIRST_MODE[name])
    lowest = red.frequencies_hz[0]
    res.append(20.0 * max(0.0, np.log(first / lowest)) if np.isfinite(first) else 5.0)
    return np.array(res), s


def report(name, s):
    t1, t2 = paper_table1_eigenfrequencies()[name], paper_table2_stiffness()[name]
    print(f"{name}: f_t {s.f_torsion_hz:.1f} ({t1['torsion']}) f_b {s.f_bending_hz:.1f} "
          f"({t1['bending']}) k {s.k_static:.3g} ({t2['k']:.3g}) k_t {s.k_t:.3g} "
          f"({t2['k_t']:.3g}) k_b {s.k_b:.3g} ({t2['k_b']:.3g})")
    for lab, ax in (("static", s.static_axis), ("torsion", s.torsion_axis),
                    ("bending", s.bending_axis)):
        if ax is not None:
            print(f"  {lab:8s} l {ax.l:8.3f} beta {np.degrees(ax.beta):6.1f} deg b {ax.b:7.3f}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("component")
    ap.add_argument("params", nargs="*")
    ap.add_argument("--weights", default="1,1,1,0.5,0.5")
    ap.add_argument("--max-factor", type=float, default=4.0)
    ap.add_argument("--out", help="write the fitted configuration (no comments) to this file")
    ap.add_argument("--match-body", help="PART=BODY:SECTION[,SECTION...] (see above)")
    ap.add_argument("--vehicle", default="touring", help="vehicle for --match-body")
    args = ap.parse_args()
    weights = [float(w) for w in args.weights.split(",")]
    data = load_yaml(resolve_config("components", args.component))
    name = data["component"]
    vehicle = load_vehicle(resolve_config("vehicles", args.vehicle)) if args.match_body else None

    def prepare(d):
        return match_body(d, args.match_body, vehicle) if args.match_body else d
    data = prepare(data)
    if args.match_body:
        part = data["rigid_parts"][args.match_body.split("=")[0]]
        print(f"{args.match_body}: mass {part['mass']:.4f} cg {np.round(part['cg'], 4).tolist()} "
              f"inertia {np.round(part['inertia'], 4).tolist()}")
    res0, s0 = residuals(name, data, weights)
    report(name, s0)
    if not args.params:
        return 0
    limits = [np.log(float(p.split("@")[1]) if "@" in p else args.max_factor)
              for p in args.params]
    args.params = [p.split("@")[0] for p in args.params]
    lim = np.array(limits)
    fit = least_squares(lambda x: residuals(name, prepare(apply(data, args.params, np.exp(x))),
                                            weights)[0],
                        np.zeros(len(args.params)), bounds=(-lim, lim), diff_step=1e-3)
    factors = np.exp(fit.x)
    fitted = prepare(apply(data, args.params, factors))
    for group, f in zip(args.params, factors):
        path = group.split(",")[0]
        if path.endswith(".*"):
            print(f"{path}: x{f:.4f} -> {_get(fitted, path[:-2])}")
        else:
            parent, key = _get_parent(fitted, path)
            print(f"{path}: x{f:.4f} -> {parent[key]:.6g}")
    report(name, residuals(name, fitted, weights)[1])
    if args.out:
        import yaml
        with open(args.out, "w", encoding="utf-8") as stream:
            yaml.safe_dump(_plain(fitted), stream, sort_keys=False)
    return 0


def _plain(obj):
    """Numpy scalars -> Python floats (rounded to 4 significant digits) for YAML output."""
    if isinstance(obj, dict):
        return {k: _plain(v) for k, v in obj.items()}
    if isinstance(obj, list):
        return [_plain(v) for v in obj]
    if isinstance(obj, (float, np.floating)):
        return float(f"{float(obj):.4g}")
    return obj


if __name__ == "__main__":
    sys.exit(main())
