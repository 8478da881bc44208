#!/usr/bin/env python3
"""Build the solid FE mesh of the touring motorcycle's main frame with gmsh (issue 15).

Usage: python tools/frame_mesh.py [--size MM] [--curvature N] [--out PATH] [--quiet]

Writes config/components/mesh/frame_mesh.msh (Gmsh 4.1 binary, millimetres, 10-node
tetrahedra curved to the tubes) for the hand-written config/components/mesh/frame_mesh.yaml,
and prints what it made (nodes, DOFs, OCC volume, element quality, times). The geometry
follows the beam frame config/components/frame.yaml, whose nodes it reads: component frame
with its origin O at the swingarm pivot, x forward, z up, y left. Parts (OD x wall [mm]):

- head tube 84 x 7.5 on the steering axis (26 deg rake) from head_lower to steering_head and
  half a bearing seat beyond both, with a bearing counterbore (72 mm, 24 deep) at each end;
  the upper seat (its cylinder and its shoulder) is the loaded end `steering_head`;
- per side: a spar 40 x 4 from the head tube back over the engine to a node at spar_mid_*
  and on to a node at spar_rear_* (the beam frame's upper and lower spars in one tube), a
  downtube 42 x 4 from the lower end of the head tube to the front engine mount, a brace
  34 x 3.5 from the spar node down to the same mount, a rear post 34 x 3.5 from the rear spar
  node down to the rear engine mount;
- the spar nodes: hollow cast balls (56 mm, 6 mm wall);
- engine mounts: a boss (short thick cylinder along y, 14 mm bolt bore: the clamp, named as
  the beam frame's engine_mount_*) at the beam frame's mount point, and a bracket plate in the
  x-z plane (front 44 x 8 mm, rear 30 x 12 mm) up to the ball where the tubes end (front:
  hollow, 60 mm, 70 mm above the bolt; rear: solid, 52 mm, 50 mm above);
- cross tubes 48 x 4 between the spar nodes (tank cross member) and between the rear spar
  nodes (rear cross tube), each carrying a sleeve along y (34 mm, 14 mm bore, 200 long) on
  two collars around the tube: the tank hangs on the tank cross member's sleeve bore (set
  `tank_mount`), the rear frame with the saddle on the rear cross tube's (`saddle_mount`).

Booleans (OpenCASCADE): the union of all outer solids minus every bore; a bore stops at the
outer surface of every part of higher rank (RANK: a spar's bore does not cut the head tube's
wall, the head tube's bore cuts away the spars' stubs inside it), so every tube is closed where
it is welded on. Tubes meet in a ball, a boss or the head tube of clearly larger radius, and
no two cylinders of nearly equal radius cross (their intersection curves would be nearly
singular and the surface mesh would self-intersect). Walls of 3.5-4 mm keep the curved
surface triangles of both sides of a wall apart at 7 elements per circle.

Mesh: size at most SIZE_MM and CURVATURE_ELEMENTS per full circle, second order with the
midside nodes on the curved surfaces, gmsh's elastic high-order untangling
(Mesh.HighOrderOptimize 3; its optimisation pass, 2, is slow here or aborts the process) and
then the midside nodes of every element whose Jacobian still changes sign pulled towards
straight (:func:`straighten_inverted`, a dozen or so). The mesh's mass is the OCC solid's
within 0.1 %. gmsh runs single-threaded (-nt 1) with a fixed
random seed. The mesh's discretisation error: first torsion and bending frequencies 1.1 %
above those of a 14 mm / 10-per-circle mesh of 213 thousand DOFs.
"""
import argparse
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import yaml

ROOT = Path(__file__).resolve().parents[1]
BEAM_FRAME = ROOT / "config" / "components" / "frame.yaml"
OUT = ROOT / "config" / "components" / "mesh" / "frame_mesh.msh"

SIZE_MM = 18.0           # largest element edge [mm]
CURVATURE_ELEMENTS = 7   # elements per full circle of a curved face (small tubes: finer)

HEAD = (84.0, 7.5)       # head tube OD x wall [mm] (frame.yaml section head)
SEAT = (72.0, 24.0)      # bearing counterbore: diameter, depth [mm]; the bearing centre (the
#                          beam node) lies half-way down the seat
SPAR = (40.0, 4.0)
DOWNTUBE = (42.0, 4.0)
BRACE = (34.0, 3.5)
POST = (34.0, 3.5)
CROSS = (48.0, 4.0)
SPAR_NODE = (56.0, 44.0)           # hollow ball at the spar joints: OD, cavity [mm]
BOLT_BORE = 14.0
# engine mounts: (boss OD, boss length along y, bracket width along x, bracket thickness along
# y, height of the tube node above the bolt, tube node ball OD, its cavity (0: solid)) [mm]
FRONT_MOUNT = (32.0, 26.0, 44.0, 8.0, 70.0, 60.0, 48.0)
REAR_MOUNT = (30.0, 22.0, 30.0, 12.0, 50.0, 52.0, 0.0)
SLEEVE = (34.0, 14.0, 200.0)       # tank / rear-frame sleeve: OD, bolt bore, length along y
SLEEVE_OVERLAP = 3.0               # how deep the sleeve sits in the cross tube's wall [mm]
PAD = (70.0, 20.0, 33.0)           # the sleeve's pads: along x, along y, reach below the
#                                    cross tube's axis [mm]: collars around the whole tube
PAD_Y = 80.0                       # the pads' distance from the symmetry plane [mm]
# where the tubes meet the steering axis: distance [mm] from head_lower towards steering_head
SPAR_AT, DOWNTUBE_AT = 115.0, 30.0
# which bore stops at which outer surface: a bore is cut short by every part of higher rank
RANK = {"head": 5, "mount": 5, "node": 4, "spar": 3, "downtube": 3, "cross": 2, "brace": 1,
        "bracket": 1, "sleeve": 0}


@dataclass
class Part:
    """A part of the frame: its outer solids and bore cutters (OCC volume tags)."""

    name: str
    kind: str
    outer: list
    bore: list


def beam_nodes():
    """The beam frame's nodes [mm] (component frame)."""
    cfg = yaml.safe_load(BEAM_FRAME.read_text())
    return {k: 1000.0 * np.asarray(v, float) for k, v in cfg["nodes"].items()}


def steering_axis(nodes):
    """Unit vector from head_lower to steering_head (the steering axis, pointing up)."""
    d = nodes["steering_head"] - nodes["head_lower"]
    return d / np.linalg.norm(d)


def sleeves(nodes):
    """(name, centre [mm], (OD, bore, length)) of the mounting sleeves along y of the tank
    (on the tank cross tube) and of the rear frame with the saddle (on the rear cross tube),
    each sitting SLEEVE_OVERLAP deep in the tube's wall."""
    lift = CROSS[0] / 2 + SLEEVE[0] / 2 - SLEEVE_OVERLAP
    mid = 0.5 * (nodes["spar_mid_left"] + nodes["spar_mid_right"])
    rear = 0.5 * (nodes["spar_rear_left"] + nodes["spar_rear_right"])
    return [("tank", mid + [0, 0, lift], SLEEVE), ("saddle", rear + [0, 0, lift], SLEEVE)]


@dataclass(frozen=True)
class Mount:
    """An engine mount: the bolt's boss (its bore is the clamp) at ``bolt`` [mm], a bracket
    plate in the x-z plane up to the ball at ``node`` [mm] where the tubes end."""

    bolt: np.ndarray
    node: np.ndarray
    boss: float
    boss_length: float
    width: float
    thickness: float
    ball: float
    cavity: float


def mounts(nodes):
    """{clamp name: Mount} of the four engine mounts (bolts at the beam frame's
    engine_mount_* nodes)."""
    out = {}
    for where, (boss, length, width, thick, height, ball, cavity) in (("front", FRONT_MOUNT),
                                                                     ("rear", REAR_MOUNT)):
        for side in ("left", "right"):
            bolt = nodes[f"engine_mount_{where}_{side}"]
            out[f"engine_mount_{where}_{side}"] = Mount(bolt, bolt + [0.0, 0.0, height], boss,
                                                        length, width, thick, ball, cavity)
    return out


def build_geometry(gmsh, nodes):
    """Add the frame's solid to the current gmsh model (OCC); return its volume tag."""
    occ = gmsh.model.occ
    parts = []

    def cylinder(p0, p1, radius):
        d = np.asarray(p1, float) - np.asarray(p0, float)
        return occ.addCylinder(*p0, *d, radius)

    def box(lo, hi):
        lo, hi = np.asarray(lo, float), np.asarray(hi, float)
        return occ.addBox(*lo, *(hi - lo))

    def tube(name, kind, p0, p1, od_wall):
        od, wall = od_wall
        parts.append(Part(name, kind, [cylinder(p0, p1, od / 2)],
                          [cylinder(p0, p1, od / 2 - wall)]))

    head_lower, steering_head = nodes["head_lower"], nodes["steering_head"]
    axis = steering_axis(nodes)
    seat_d, depth = SEAT
    bottom, top = head_lower - depth / 2 * axis, steering_head + depth / 2 * axis
    parts.append(Part("head", "head", [cylinder(bottom, top, HEAD[0] / 2)],
                      [cylinder(bottom, top, HEAD[0] / 2 - HEAD[1]),
                       cylinder(top - depth * axis, top, seat_d / 2),
                       cylinder(bottom, bottom + depth * axis, seat_d / 2)]))
    for side in ("left", "right"):
        mid, rear = nodes[f"spar_mid_{side}"], nodes[f"spar_rear_{side}"]
        front = mounts(nodes)[f"engine_mount_front_{side}"].node
        back = mounts(nodes)[f"engine_mount_rear_{side}"].node
        tube(f"spar_{side}", "spar", head_lower + SPAR_AT * axis, mid, SPAR)
        tube(f"rear_spar_{side}", "spar", mid, rear, SPAR)
        tube(f"downtube_{side}", "downtube", head_lower + DOWNTUBE_AT * axis, front, DOWNTUBE)
        tube(f"brace_{side}", "brace", mid, front, BRACE)
        tube(f"post_{side}", "brace", rear, back, POST)
        for where, centre in (("mid", mid), ("rear", rear)):
            parts.append(Part(f"spar_node_{where}_{side}", "node",
                              [occ.addSphere(*centre, SPAR_NODE[0] / 2)],
                              [occ.addSphere(*centre, SPAR_NODE[1] / 2)]))
    for name, m in mounts(nodes).items():
        half = np.array([0.0, m.boss_length / 2, 0.0])
        parts.append(Part(name, "mount", [cylinder(m.bolt - half, m.bolt + half, m.boss / 2)],
                          [cylinder(m.bolt - half, m.bolt + half, BOLT_BORE / 2)]))
        parts.append(Part(f"{name}_node", "node", [occ.addSphere(*m.node, m.ball / 2)],
                          [occ.addSphere(*m.node, m.cavity / 2)] if m.cavity else []))
        plate = np.array([m.width / 2, m.thickness / 2, 0.0])
        parts.append(Part(f"{name}_bracket", "bracket", [box(m.bolt - plate, m.node + plate)],
                          []))
    for (name, centre, (od, bore, length)), ends in zip(
            sleeves(nodes), (("spar_mid_right", "spar_mid_left"),
                             ("spar_rear_right", "spar_rear_left"))):
        tube(f"{name}_cross", "cross", nodes[ends[0]], nodes[ends[1]], CROSS)
        axis_z = 0.5 * (nodes[ends[0]][2] + nodes[ends[1]][2])
        pads = [box([centre[0] - PAD[0] / 2, y - PAD[1] / 2, axis_z - PAD[2]],
                    [centre[0] + PAD[0] / 2, y + PAD[1] / 2, centre[2]])
                for y in (-PAD_Y, PAD_Y)]
        half = np.array([0.0, length / 2, 0.0])
        parts.append(Part(f"{name}_sleeve", "sleeve",
                          [cylinder(centre - half, centre + half, od / 2)] + pads,
                          [cylinder(centre - half, centre + half, bore / 2)]))

    # each bore stops at the outer surface of every part of higher rank that it reaches
    def bbox(tag):
        b = np.asarray(occ.getBoundingBox(3, tag))
        return b[:3], b[3:]

    boxes = {t: bbox(t) for p in parts for t in p.outer + p.bore}
    cutters = []
    for part in parts:
        for bore in part.bore:
            lo, hi = boxes[bore]
            higher = [(3, t) for q in parts if RANK[q.kind] > RANK[part.kind] for t in q.outer
                      if np.all(boxes[t][0] <= hi) and np.all(boxes[t][1] >= lo)]
            if higher:
                out, _ = occ.cut([(3, bore)], higher, removeObject=True, removeTool=False)
                cutters.extend(out)
            else:
                cutters.append((3, bore))
    outers = [(3, t) for p in parts for t in p.outer]
    solid, _ = occ.fuse(outers[:1], outers[1:])
    occ.cut(solid, cutters)
    occ.synchronize()
    volumes = gmsh.model.getEntities(3)
    if len(volumes) != 1:
        raise RuntimeError(f"the frame is {len(volumes)} volumes, not one")
    return volumes[0][1]


def face_samples(gmsh, tag, n=7):
    """Points [mm] on face ``tag``: its boundary curves sampled, and a uv grid kept where it
    lies on the (trimmed) face."""
    pts = []
    for _, t in gmsh.model.getBoundary([(2, tag)], oriented=False):
        lo, hi = gmsh.model.getParametrizationBounds(1, t)
        pts.append(np.reshape(gmsh.model.getValue(1, t, np.linspace(lo[0], hi[0], 2 * n)),
                              (-1, 3)))
    lo, hi = gmsh.model.getParametrizationBounds(2, tag)
    for u in np.linspace(lo[0], hi[0], n):
        for v in np.linspace(lo[1], hi[1], n):
            if gmsh.model.isInside(2, tag, [u, v], parametric=True):
                pts.append(np.reshape(gmsh.model.getValue(2, tag, [u, v]), (1, 3)))
    return np.vstack(pts)


def _radial(p, centre, direction):
    """(axial, radial) coordinates [mm] of points p about the line through centre along the
    unit direction."""
    rel = np.asarray(p, float) - centre
    s = rel @ direction
    return s, np.linalg.norm(rel - np.outer(s, direction), axis=1)


def on_cylinder(centre, direction, radius, half_length, tol=1e-3):
    """Predicate: on the cylinder of ``radius`` about the line through ``centre`` along the
    unit ``direction``, within ``half_length`` of ``centre``."""
    def test(p):
        s, r = _radial(p, centre, direction)
        return (np.abs(s) <= half_length + tol) & (np.abs(r - radius) <= tol)
    return test


def bearing_seat(centre, axis, tol=1e-3):
    """Predicate: on the upper bearing seat (the counterbore's cylinder and its shoulder) of the
    head tube, whose bearing centre is ``centre`` on the unit steering ``axis``."""
    seat_d, depth = SEAT
    cylinder = on_cylinder(centre, axis, seat_d / 2, depth / 2, tol)

    def test(p):
        s, r = _radial(p, centre, axis)
        shoulder = ((np.abs(s + depth / 2) <= tol) & (r >= HEAD[0] / 2 - HEAD[1] - tol)
                    & (r <= seat_d / 2 + tol))
        return cylinder(p) | shoulder
    return test


def group_predicates(nodes):
    """{surface group name: predicate on points [mm]} of the frame's named faces."""
    y = np.array([0.0, 1.0, 0.0])
    groups = {name: on_cylinder(m.bolt, y, BOLT_BORE / 2, m.boss_length / 2)
              for name, m in mounts(nodes).items()}
    groups["steering_head"] = bearing_seat(nodes["steering_head"], steering_axis(nodes))
    for name, centre, (_, bore, length) in sleeves(nodes):
        groups[f"{name}_mount"] = on_cylinder(centre, y, bore / 2, length / 2)
    return groups


def add_groups(gmsh, volume, nodes):
    """Physical groups: the volume 'frame' and the named faces; {name: face tags}."""
    gmsh.model.addPhysicalGroup(3, [volume], name="frame")
    samples = {tag: face_samples(gmsh, tag) for _, tag in gmsh.model.getEntities(2)}
    groups = {}
    for name, predicate in group_predicates(nodes).items():
        tags = [tag for tag, pts in samples.items() if np.all(predicate(pts))]
        if not tags:
            raise RuntimeError(f"no face found for the group {name}")
        gmsh.model.addPhysicalGroup(2, tags, name=name)
        groups[name] = tags
    return groups


TET10_EDGES = ((0, 1), (1, 2), (2, 0), (3, 0), (3, 2), (3, 1))   # gmsh's 10-node tetrahedron


def straighten_inverted(gmsh, tets, rounds=20):
    """Pull the midside nodes of every element whose Jacobian determinant is not positive
    somewhere (gmsh's minDetJac, a bound over the whole element) towards the midpoints of its
    edges, by the least tenth of their offsets that makes it valid (a straight-sided 10-node
    tetrahedron is valid whenever its corners are); repeat while a moved node turns a
    neighbour. Return how many elements were moved: a dozen or so, which leave the curved
    surfaces they touch by a fraction of a millimetre and add 0.06 % to the frame's mass."""
    mesh = gmsh.model.mesh

    def inverted(tags):
        return tags[np.asarray(mesh.getElementQualities(tags, "minDetJac")) <= 0.0]

    done = set()
    for _ in range(rounds):
        bad = inverted(tets)
        if len(bad) == 0:
            return len(done)
        for tag in bad:
            _, nodes, _, _ = mesh.getElement(int(tag))
            xyz = np.array([mesh.getNode(int(n))[0] for n in nodes])
            chord = np.array([0.5 * (xyz[a] + xyz[b]) for a, b in TET10_EDGES])
            for keep in np.linspace(0.9, 0.0, 10):
                for k, n in enumerate(nodes[4:]):
                    mesh.setNode(int(n), list(chord[k] + keep * (xyz[4 + k] - chord[k])), [])
                if len(inverted(np.array([tag]))) == 0:
                    break
            done.add(int(tag))
    bad = inverted(tets)
    if len(bad):
        raise RuntimeError(f"{len(bad)} elements are still inverted after straightening")
    return len(done)


def geometry_volume():
    """The frame's volume [mm^3] as OpenCASCADE computes it (no mesh)."""
    import gmsh
    gmsh.initialize(["-nt", "1"], readConfigFiles=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add("frame")
        return gmsh.model.occ.getMass(3, build_geometry(gmsh, beam_nodes()))
    finally:
        gmsh.finalize()


def build(out=OUT, size=SIZE_MM, curvature=CURVATURE_ELEMENTS, verbose=True):
    """Build, mesh and write the frame; return a dict of what was made."""
    import gmsh
    nodes = beam_nodes()
    gmsh.initialize(["-nt", "1"], readConfigFiles=False)
    try:
        gmsh.option.setNumber("General.Terminal", 1 if verbose else 0)
        gmsh.model.add("frame")
        t0 = time.perf_counter()
        volume = build_geometry(gmsh, nodes)
        occ_volume = gmsh.model.occ.getMass(3, volume)
        groups = add_groups(gmsh, volume, nodes)
        t1 = time.perf_counter()
        for option, value in (("Mesh.MeshSizeMax", size), ("Mesh.MeshSizeMin", 0.5),
                              ("Mesh.MeshSizeFromCurvature", curvature),
                              ("Mesh.ElementOrder", 2), ("Mesh.SecondOrderLinear", 0),
                              ("Mesh.HighOrderOptimize", 3), ("Mesh.MshFileVersion", 4.1),
                              ("Mesh.Binary", 1), ("General.NumThreads", 1),
                              ("Mesh.RandomSeed", 1.0)):
            gmsh.option.setNumber(option, value)
        gmsh.model.mesh.generate(3)
        _, elements, _ = gmsh.model.mesh.getElements(3, volume)
        tets = np.concatenate(elements)
        straightened = straighten_inverted(gmsh, tets)
        t2 = time.perf_counter()
        out = Path(out)
        out.parent.mkdir(parents=True, exist_ok=True)
        gmsh.write(str(out))
        node_tags, _, _ = gmsh.model.mesh.getNodes(3, volume, includeBoundary=True)
        jacobian = np.asarray(gmsh.model.mesh.getElementQualities(tets, "minDetJac"))
        shape = np.asarray(gmsh.model.mesh.getElementQualities(tets, "minSICN"))
        report = {"file": str(out), "bytes": out.stat().st_size, "nodes": len(node_tags),
                  "dofs": 3 * len(node_tags), "elements": len(tets),
                  "occ_volume_mm3": occ_volume, "steel_mass_kg": occ_volume * 7850e-9,
                  "straightened": straightened, "min_jacobian": float(jacobian.min()),
                  "min_shape_quality": float(shape.min()),
                  "shape_quality_below_0.1": int(np.sum(shape < 0.1)),
                  "faces": groups, "geometry_s": t1 - t0, "mesh_s": t2 - t1}
    finally:
        gmsh.finalize()
    return report


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--size", type=float, default=SIZE_MM, help="largest element edge [mm]")
    parser.add_argument("--curvature", type=float, default=CURVATURE_ELEMENTS,
                        help="elements per full circle of a curved face")
    parser.add_argument("--out", default=str(OUT), help="the .msh file to write")
    parser.add_argument("--quiet", action="store_true", help="no gmsh log")
    args = parser.parse_args(argv)
    report = build(args.out, args.size, args.curvature, verbose=not args.quiet)
    for key, value in report.items():
        print(f"{key}: {value}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
