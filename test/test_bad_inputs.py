"""Inputs that once crashed or ran away (issue 13, point 5), and more of the same kind.

Each case runs the real command in a process of its own on a file written for it and must:
exit non-zero, print no traceback, name the file (or the command line / node) and the key, end
within 5 s of computing (a hang guard: the work is sized before it starts; see run_guarded)
and leave no output file. The motoflex command's process is forked from the test's, with the
package already imported (run_forked); a node's is a fresh interpreter.
"""
import importlib
import os
import pkgutil
import signal
import subprocess
import sys
import tempfile
import time
import traceback
from dataclasses import dataclass, field
from pathlib import Path

import pytest

from motoflex_ros.config import config_path

HANG_GUARD_S = 5.0  # [s] of the command's CPU time
WALL_GUARD_S = 60.0  # [s]
CLI = [sys.executable, "-m", "motoflex_ros.cli.main"]
NODE = [sys.executable, "-m", "motoflex_ros.nodes.vehicle_simulator", "--ros-args"]


def shipped(kind, name, *edits):
    """The text of a shipped config with each (old, new) replacement made (old must occur)."""
    text = config_path(kind, name).read_text()
    for old, new in edits:
        assert old in text, (kind, name, old)
        text = text.replace(old, new, 1)
    return text


def with_value(kind, name, keys, value):
    """The YAML of a shipped config with the value at ``keys`` (a path of mapping keys) set."""
    import yaml
    data = yaml.safe_load(config_path(kind, name).read_text())
    node = data
    for key in keys[:-1]:
        node = node[key]
    assert keys[-1] in node, (kind, name, keys)
    node[keys[-1]] = value
    return yaml.safe_dump(data)


def ref(name):
    """The placeholder of a written file's path in a case's argv."""
    return "{" + name + "}"


def params(**values):
    """A vehicle_simulator params file."""
    lines = "".join(f"    {k}: {v}\n" for k, v in values.items())
    return f"vehicle_simulator:\n  ros__parameters:\n{lines}"


@dataclass(frozen=True)
class Case:
    """argv (``{name}`` replaced by the path of the written file ``name``), files {name: text
    or bytes}, what the message must name: the file (or 'command line'/node) and the key."""

    argv: tuple
    files: dict = field(default_factory=dict)
    where: str = ""
    key: str = ""
    node: bool = False


TUBE = "tube.yaml"
FRAME = "frame.yaml"
PROTO = "protocol.yaml"
VEHICLE = "vehicle.yaml"


def tube(*edits):
    return {TUBE: shipped("components", "tube", *edits)}


def frame(*edits):
    return {FRAME: shipped("components", "frame", *edits)}


def protocol(*edits):
    return {PROTO: shipped("protocols", "default", *edits)}


def vehicle(*edits):
    return {VEHICLE: shipped("vehicles", "touring", *edits)}


COMPONENTS = ("components", "--component")
IDENTIFY_TUBE = ("identify", "--component", "tube", "--protocol", ref(PROTO),
                 "--out", "{out.json}")
EIG = ("eig", "--vehicle", ref(VEHICLE), "--speeds-ms", "10")
EIG_ARGS = ("eig", "--vehicle", "whipple_benchmark")
STEEL = "steel: {E: 2.1e11, G: 8.1e10, rho: 7850}"

ISSUE_CASES = {
    # rho twice: the last won silently (f_t 78.9 instead of 74.6 Hz)
    "duplicate_key": Case(COMPONENTS + (ref(FRAME),),
                          frame((STEEL, "steel: {E: 2.1e11, G: 8.1e10, rho: 7850, rho: 9000}")),
                          FRAME, "materials.steel.rho"),
    # UnicodeDecodeError traceback
    "binary_component": Case(COMPONENTS + ("{part.yaml}",),
                             {"part.yaml": b"\x89PNG\r\n\x1a\n\xff\xfe\x00garbage"},
                             "part.yaml", "UTF-8"),
    # ZeroDivisionError traceback
    "outer_diameter_1e6": Case(COMPONENTS + (ref(FRAME),), frame(
        ("head: {shape: tube, outer_diameter: 0.084", "head: {shape: tube, outer_diameter: 1e6")),
        FRAME, "sections.head.outer_diameter"),
    # "interior stiffness is singular" without file or key
    "E_1e300": Case(COMPONENTS + (ref(FRAME),), frame(("E: 2.1e11", "E: 1.0e300")),
                    FRAME, "materials.steel.E"),
    # 2.9 GB after 45 s and growing
    "max_element_length_1e-7": Case(COMPONENTS + (ref(FRAME),), frame(
        ("max_element_length: 0.05", "max_element_length: 1.0e-7")),
        FRAME, "mesh.max_element_length"),
    # identify hung; the campaign planned 13.4 million simulated seconds
    "decay_periods_1e9": Case(IDENTIFY_TUBE, protocol(("decay_periods: 20", "decay_periods: 1e9")),
                              PROTO, "modal.decay_periods"),
    "campaign_decay_periods_1e9": Case(
        ("campaign", "--component", "tube", "--protocol", ref(PROTO), "--report", "none",
         "--out", "{bag}"), protocol(("decay_periods: 20", "decay_periods: 1e9")),
        PROTO, "modal.decay_periods"),
    # MemoryError tracebacks
    "eig_speeds_1e12": Case(EIG_ARGS + ("--speeds-ms", "1e12"), {}, "command line", "--speeds"),
    "eig_step_1e-9": Case(EIG_ARGS + ("--range-kmh", "10", "200", "--step-kmh", "1e-9"), {},
                          "command line", "--step"),
    # blamed on the tyre key pky1
    "vehicle_mass_1e300": Case(EIG, {VEHICLE: with_value(
        "vehicles", "touring", ("bodies", "frame", "parts", "frame_engine", "mass"), 1e300)},
        VEHICLE, "bodies.frame.parts.frame_engine.mass"),
    # accepted: "0 speeds"
    "speed_min_above_max": Case(("--params-file", "{p.yaml}"),
                                {"p.yaml": params(speed_min_kmh=300.0, speed_max_kmh=100.0)},
                                "vehicle_simulator", "speed_min_kmh", node=True),
    # RCLError tracebacks
    "params_file_missing": Case(("--params-file", "{missing.yaml}"), {}, "missing.yaml",
                                "not found", node=True),
    "params_file_garbage": Case(("--params-file", "{p.yaml}"), {"p.yaml": b"\x00\x01garbage: ["},
                                "p.yaml", "not valid YAML", node=True),
    # traceback
    "result_file_missing": Case(("-p", "result_file:={missing.json}"), {}, "missing.json",
                                "result_file", node=True),
}

MORE_CASES = {
    "duplicate_top_level_key": Case(COMPONENTS + (ref(TUBE),),
                                    tube(("elements: 20", "elements: 20\nelements: 40")),
                                    TUBE, "elements"),
    "yaml_syntax_error": Case(COMPONENTS + (ref(TUBE),),
                              tube(("elements: 20", "elements: [20")), TUBE, "line"),
    "empty_file": Case(COMPONENTS + (ref(TUBE),), {TUBE: "# nothing\n"}, TUBE, "empty"),
    "nul_character": Case(COMPONENTS + (ref(TUBE),), {TUBE: "component: tube\x00\n"},
                          TUBE, "not valid YAML"),
    "file_too_large": Case(COMPONENTS + (ref(TUBE),),
                           {TUBE: "component: tube\n" + "# padding\n" * 200_000}, TUBE,
                           "too large"),
    "integer_with_400_digits": Case(COMPONENTS + (ref(TUBE),),
                                    tube(("E: 2.1e11", "E: 1" + "0" * 400)), TUBE, "material.E"),
    "tube_length_1e6": Case(COMPONENTS + (ref(TUBE),),
                            tube(("length: 0.6", "length: 1.0e6")), TUBE, "tube.length"),
    "wall_thickness_1e300": Case(COMPONENTS + (ref(TUBE),),
                                 tube(("wall_thickness: 0.002", "wall_thickness: 1.0e300")), TUBE,
                                 "tube.wall_thickness"),
    "tube_elements_dof_limit": Case(COMPONENTS + (ref(TUBE),),
                                    tube(("elements: 20", "elements: 100000")), TUBE, "elements"),
    "mesh_dof_limit": Case(COMPONENTS + (ref(FRAME),), frame(
        ("max_element_length: 0.05", "max_element_length: 1.0e-4")), FRAME,
        "mesh.max_element_length"),
    "spring_1e300": Case(COMPONENTS + (ref(FRAME),), frame(
        ("k_translation: [1.0e8, 2.392e7", "k_translation: [1.0e300, 2.392e7")), FRAME,
        "springs[0].k_translation[0]"),
    "rigid_part_mass_1e300": Case(COMPONENTS + (ref(FRAME),), frame(
        ("mass: 11.8", "mass: 1.0e300")), FRAME, "rigid_parts.tank.mass"),
    "node_coordinate_1e300": Case(COMPONENTS + (ref(FRAME),), frame(
        ("steering_head: [0.6216", "steering_head: [1.0e300")), FRAME, "nodes.steering_head[0]"),
    "component_is_a_directory": Case(COMPONENTS + ("{dir.yaml}",), {"dir.yaml/x": "a: 1"},
                                     "dir.yaml", "is a directory, not a regular file"),
    "protocol_duplicate_key": Case(IDENTIFY_TUBE, protocol(
        ("force_n: 100.0", "force_n: 100.0\n  force_n: 200.0")), PROTO, "static.force_n"),
    "protocol_top_level_list": Case(IDENTIFY_TUBE, {PROTO: "- 1\n- 2\n"}, PROTO, "top level"),
    "hold_time_1e9": Case(IDENTIFY_TUBE, protocol(("hold_time_s: 0.4", "hold_time_s: 1.0e9")),
                          PROTO, "static.hold_time_s"),
    "sample_rate_1e300": Case(IDENTIFY_TUBE, protocol(
        ("sample_rate_hz: 1000.0", "sample_rate_hz: 1.0e300")), PROTO, "static.sample_rate_hz"),
    "decay_samples_limit": Case(IDENTIFY_TUBE, protocol(("decay_periods: 20",
                                                         "decay_periods: 90000")),
                                PROTO, "modal.decay_periods"),
    "simulated_time_limit": Case(IDENTIFY_TUBE, protocol(("max_periods: 40", "max_periods: 9000")),
                                 PROTO, "harmonic.max_periods"),
    "sweep_step_1e-6": Case(IDENTIFY_TUBE, protocol(("step_hz: 10.0", "step_hz: 1.0e-6")),
                            PROTO, "sweep.step_hz"),
    # found by trying every number of the shipped files at its allowed bounds
    "preload_1e-300": Case(IDENTIFY_TUBE, protocol(("preload_n: 300.0", "preload_n: 1.0e-300")),
                           PROTO, "modal.preload_n"),
    "onset_beat_cycles_1000": Case(IDENTIFY_TUBE, protocol(("onset_beat_cycles: 4.0",
                                                            "onset_beat_cycles: 1000.0")),
                                   PROTO, "harmonic.onset_beat_cycles"),
    "tyre_Fz0_1e-300": Case(EIG, vehicle(("Fz0: 1600.0", "Fz0: 1.0e-300")), VEHICLE,
                            "wheels.rear.tyre.Fz0"),
    "vehicle_duplicate_key": Case(EIG, vehicle(("gravity: 9.81", "gravity: 9.81\ngravity: 1.6")),
                                  VEHICLE, "gravity"),
    "vehicle_gravity_1e300": Case(EIG, vehicle(("gravity: 9.81", "gravity: 1.0e300")), VEHICLE,
                                  "gravity"),
    "wheel_radius_1e300": Case(EIG, vehicle(("radius: 0.300", "radius: 1.0e300")), VEHICLE,
                               "wheels.front.radius"),
    "tyre_Fz0_1e300": Case(EIG, vehicle(("Fz0: 1100.0", "Fz0: 1.0e300")), VEHICLE,
                           "wheels.front.tyre.Fz0"),
    "wheels_at_one_x": Case(EIG, vehicle(("centre: [1.485, 0.0, 0.300]",
                                          "centre: [0.0, 0.0, 0.300]")), VEHICLE,
                            "wheels.rear.centre"),
    "binary_vehicle": Case(EIG, {VEHICLE: bytes(range(256))}, VEHICLE, "UTF-8"),
    "eig_top_speed": Case(EIG_ARGS + ("--range-kmh", "10", "2000", "--step-kmh", "1"), {},
                          "command line", "--range-kmh"),
    "eig_many_speeds": Case(EIG_ARGS + ("--speeds-ms",) + ("1",) * 10_001, {}, "command line",
                            "--speeds"),
    "study_step_1e-9": Case(("study", "accuracy", "--step-kmh", "1e-9", "--plot", "{plots}"), {},
                            "command line", "--step-kmh"),
    "identified_file_garbage": Case(("eig", "--vehicle", "touring", "--speeds-ms", "10", "--flex",
                                                    "static", "--identified", "{r.json}"),
                                    {"r.json": "{\"frame\": [1, 2"}, "r.json", "not valid YAML"),
    "bad_limit_value": Case(EIG_ARGS + ("--speeds-ms", "10", "--limit", "speeds=-1"), {},
                            "--limit", "speeds"),
    "params_file_binary": Case(("--params-file", "{p.yaml}"), {"p.yaml": bytes(range(256))},
                               "p.yaml", "UTF-8", node=True),
    "params_file_duplicate_key": Case(("--params-file", "{p.yaml}"), {"p.yaml": params(
        speed_min_kmh=40.0) + "    speed_min_kmh: 50.0\n"}, "p.yaml",
        "vehicle_simulator.ros__parameters.speed_min_kmh", node=True),
    "parameter_value_rcl_refuses": Case(("-p", "speed_min_kmh:=[1, a]"), {}, "ROS arguments",
                                        "speed_min_kmh", node=True),
    "result_file_binary": Case(("-p", "result_file:={r.json}"), {"r.json": bytes(range(256))},
                               "r.json", "result_file", node=True),
    "result_file_without_a_component": Case(("-p", "result_file:={r.json}"),
                                            {"r.json": "{\"frame\": {}}"}, "r.json",
                                            "front_assembly", node=True),
}



def _mesh_texts():
    """Texts of small mesh files (issue 15): a box of linear tetrahedra in Abaqus .inp with the
    node sets clamp (x = 0), tip (x = 0.2), edge (three nodes on one line) and near (the clamp
    face's nodes plus one of the tip's); a copy with one element's nodes swapped (inverted), one
    with an element whose four nodes are coplanar (zero volume), one in mm read as m, a mesh of
    wedges and a mesh of surface triangles only (VTU)."""
    import meshio
    import numpy as np

    from motoflex_ros.formats.mesh_examples import box_mesh, write_mesh
    points, cells = box_mesh(0.2, 0.02, 0.02, (4, 1, 1), "tetra")
    x, y, z = points.T
    clamp, tip = np.flatnonzero(np.isclose(x, 0)), np.flatnonzero(np.isclose(x, 0.2))
    sets = {"clamp": clamp, "tip": tip,
            "edge": np.flatnonzero(np.isclose(y, y.min()) & np.isclose(z, z.min())
                                   & (x > 0.01) & (x < 0.19)),
            "near": np.append(clamp, tip[0])}
    inverted = cells.copy()
    inverted[3, [1, 2]] = inverted[3, [2, 1]]
    flat = cells.copy()
    flat[5, 3] = flat[5, 0]   # element 6 has a node twice: zero volume
    texts = {}
    with tempfile.TemporaryDirectory() as tmp:
        for name, pts, cl, units in (("good", points, cells, "m"), ("inverted", points,
                                                                    inverted, "m"),
                                     ("flat", points, flat, "m"),
                                     ("big", points * 100, cells, "mm")):
            path = Path(tmp) / f"{name}.inp"
            write_mesh(path, pts, cl, "tetra", sets, units)
            texts[name] = path.read_text()
        wedge = Path(tmp) / "wedge.vtu"
        meshio.write(str(wedge), meshio.Mesh(points[:6], [("wedge", np.array([[0, 1, 2, 3, 4,
                                                                             5]]))]))
        texts["wedge"] = wedge.read_text()
        surface = Path(tmp) / "surface.vtu"
        meshio.write(str(surface), meshio.Mesh(points, [("triangle", cells[:, :3])],
                                               point_data={"clamp": np.isin(
                                                   np.arange(len(points)), clamp).astype(int)}))
        texts["surface"] = surface.read_text()
    return texts


MESH_TEXTS = _mesh_texts()
PART = "part.yaml"
PART_YAML = """component: mesh
mesh: {file: box.inp, units: m, clamps: [clamp], loaded_end: tip}
material: {E: 7.0e10, nu: 0.33, rho: 2700}
"""


def part(mesh="good", *edits, mesh_name="box.inp"):
    """A mesh component YAML (PART) with its mesh file, each (old, new) edit made to the YAML."""
    text = PART_YAML.replace("box.inp", mesh_name)
    for old, new in edits:
        assert old in text, old
        text = text.replace(old, new, 1)
    return {PART: text, mesh_name: MESH_TEXTS[mesh]}


MESH_CASES = {
    "mesh_file_missing": Case(COMPONENTS + (ref(PART),), {PART: PART_YAML}, PART,
                              "mesh.file"),
    "mesh_unknown_set": Case(COMPONENTS + (ref(PART),), part("good", ("[clamp]", "[pivot]")),
                             PART, "mesh.clamps[0]"),
    "mesh_set_names_the_mesh_file": Case(IDENTIFY_MESH := ("identify", "--component",
                                                           ref(PART), "--out", "{o.json}"),
                                         part("good", ("loaded_end: tip", "loaded_end: axle")),
                                         "box.inp", "mesh.loaded_end"),
    "mesh_unsupported_element": Case(COMPONENTS + (ref(PART),),
                                     part("wedge", mesh_name="box.vtu"), PART, "wedge"),
    "mesh_units_not_m_or_mm": Case(COMPONENTS + (ref(PART),),
                                   part("good", ("units: m", "units: inch")), PART,
                                   "mesh.units"),
    "mesh_mm_read_as_m": Case(COMPONENTS + (ref(PART),), part("big"), PART, "mesh.units"),
    "mesh_zero_volume_element": Case(COMPONENTS + (ref(PART),), part("flat"), PART,
                                     "tetra element 6"),
    "mesh_inverted_element": Case(IDENTIFY_MESH, part("inverted"), PART, "tetra element 4"),
    "mesh_without_volume_elements": Case(COMPONENTS + (ref(PART),),
                                         part("surface", mesh_name="box.vtu"), "box.vtu",
                                         "no volume elements"),
    "mesh_collinear_set": Case(COMPONENTS + (ref(PART),),
                               part("good", ("loaded_end: tip", "loaded_end: edge")), PART,
                               "on one line"),
    "mesh_sets_share_nodes": Case(COMPONENTS + (ref(PART),),
                                  part("good", ("loaded_end: tip", "loaded_end: near")), PART,
                                  "mesh.loaded_end"),
    "mesh_unreadable": Case(COMPONENTS + (ref(PART),),
                            {PART: PART_YAML.replace("box.inp", "box.msh"),
                             "box.msh": "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n"
                                        "garbage\n"}, "box.msh", "meshio cannot read"),
    "mesh_unsupported_format": Case(COMPONENTS + (ref(PART),),
                                    {PART: PART_YAML.replace("box.inp", "box.stl"),
                                     "box.stl": "solid x\nendsolid x\n"}, PART, "mesh.file"),
    "mesh_too_many_dofs": Case(COMPONENTS + (ref(PART), "--limit", "mesh_dofs=50"),
                               part("good"), PART, "mesh_dofs"),
    "mesh_nu_out_of_range": Case(COMPONENTS + (ref(PART),),
                                 part("good", ("nu: 0.33", "nu: 0.5")), PART, "material.nu"),
}

CASES = {**ISSUE_CASES, **MORE_CASES, **MESH_CASES}


def test_enough_cases():
    """Every case of issue 13 point 5 and at least 20 more."""
    assert len(ISSUE_CASES) >= 11 and len(MORE_CASES) >= 20


def _write(folder, files):
    for name, content in files.items():
        path = folder / name
        path.parent.mkdir(parents=True, exist_ok=True)
        if isinstance(content, bytes):
            path.write_bytes(content)
        else:
            path.write_text(content)


def _argv(case, folder):
    names = {part[1:-1] for part in case.argv if part.startswith("{") and part.endswith("}")}
    names |= {part.split("{")[1][:-1] for part in case.argv if ":={" in part}
    out = []
    for part in case.argv:
        for name in names:
            part = part.replace(ref(name), str(folder / name))
        out.append(part)
    return out


def _cpu_seconds(pid):
    """User + system CPU time [s] of a running process (Linux /proc)."""
    try:
        fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    except (OSError, IndexError):
        return 0.0
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def _check_guards(pid, start):
    """The hang guards of a running child ``pid`` started at monotonic time ``start``: at most
    HANG_GUARD_S of its own CPU time and WALL_GUARD_S of wall time."""
    cpu, wall = _cpu_seconds(pid), time.monotonic() - start
    assert cpu < HANG_GUARD_S, f"still running after {cpu:.1f} s of CPU: runs away"
    assert wall < WALL_GUARD_S, f"still running after {wall:.0f} s: hangs"


def run_guarded(cmd, env, cwd):
    """Run ``cmd`` to its end; fail if it computes for more than HANG_GUARD_S seconds of CPU
    (the work was not sized before it started) or lives WALL_GUARD_S (it waits for nothing).

    The hang guard counts the process's own CPU time, not the wall clock: on the shared test
    machine (two cores, several suites at once) a refusal that computes 1 s took 5 s of wall
    time, while each case of issue 13.5 computed for minutes or without end."""
    start = time.monotonic()
    with tempfile.TemporaryFile("w+") as out, tempfile.TemporaryFile("w+") as err:
        proc = subprocess.Popen(cmd, stdout=out, stderr=err, env=env, cwd=cwd, text=True)
        try:
            while proc.poll() is None:
                _check_guards(proc.pid, start)
                time.sleep(0.05)
        finally:
            if proc.poll() is None:
                proc.kill()
                proc.wait()
        out.seek(0)
        err.seek(0)
        return subprocess.CompletedProcess(cmd, proc.returncode, out.read(), err.read())


def _child_main(argv, env, cwd, out, err):
    """In a forked child: run ``motoflex argv`` as ``python -m motoflex_ros.cli.main`` would
    (stdout and stderr on the files ``out`` and ``err``, ``env`` as its environment, ``cwd``
    its folder, an uncaught exception printed as a traceback and exit 1); never returns."""
    code = 1
    try:
        os.chdir(cwd)
        os.dup2(out.fileno(), 1)
        os.dup2(err.fileno(), 2)
        sys.stdout = open(1, "w", closefd=False)
        sys.stderr = open(2, "w", closefd=False)
        os.environ.clear()
        os.environ.update(env)
        from motoflex_ros.cli.main import main
        try:
            code = main([str(a) for a in argv])
        except SystemExit as exc:
            code = exc.code if isinstance(exc.code, int) else int(exc.code is not None)
        code = 0 if code is None else code
    except BaseException:   # what the interpreter would print before exiting 1
        traceback.print_exc()
        code = 1
    finally:
        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(code)


def run_forked(argv, env, cwd):
    """``motoflex argv`` in a child forked from this process, with the hang guards of
    :func:`run_guarded`. The child starts with the command's modules already imported
    (:data:`WARM_MODULES`): a fresh interpreter spent 1.5-2 s of CPU importing numpy, scipy
    and the package before each refusal, most of this file's time, and none of what it tests.
    """
    start = time.monotonic()
    with tempfile.TemporaryFile("w+") as out, tempfile.TemporaryFile("w+") as err:
        pid = os.fork()
        if pid == 0:
            _child_main(argv, env, cwd, out, err)
        code = None
        try:
            while code is None:
                done, status = os.waitpid(pid, os.WNOHANG)
                if done:
                    code = os.waitstatus_to_exitcode(status)
                    break
                _check_guards(pid, start)
                time.sleep(0.02)
        finally:
            if code is None:
                os.kill(pid, signal.SIGKILL)
                os.waitpid(pid, 0)
        out.seek(0)
        err.seek(0)
        return subprocess.CompletedProcess(argv, code, out.read(), err.read())


WARM_MODULES = ("numpy", "scipy.linalg", "scipy.sparse", "scipy.sparse.linalg", "scipy.signal",
                "scipy.optimize", "yaml", "motoflex_ros.cli.main")
"""Imported once before the children are forked (plus every module of the package's core and
formats, cli, report and plots, by :func:`_warm_imports`)."""


def _warm_imports():
    for name in WARM_MODULES:
        importlib.import_module(name)
    root = Path(__import__("motoflex_ros").__file__).parent
    for package in ("structures", "identify", "vehicle", "bench", "study", "formats", "cli",
                    "lumped_stiffness"):
        for info in pkgutil.iter_modules([str(root / package)]):
            importlib.import_module(f"motoflex_ros.{package}.{info.name}")


def assert_refused(case, folder, cmd, env):
    """Run ``cmd`` (the case's files written into ``folder``): non-zero exit, no traceback, the
    file and key named on stderr, no file left behind. The motoflex command runs in a forked
    child (:func:`run_forked`), anything else (a node) in a fresh process."""
    _write(folder, case.files)
    before = sorted(folder.rglob("*"))
    if cmd == CLI:
        result = run_forked(_argv(case, folder), env, folder)
    else:
        result = run_guarded(cmd + _argv(case, folder), env, folder)
    output = result.stdout + result.stderr
    assert result.returncode != 0, output
    assert "Traceback" not in output, output
    assert case.where in result.stderr and case.key in result.stderr, result.stderr
    assert sorted(folder.rglob("*")) == before, "an output file was left"


@pytest.fixture(scope="module")
def warm():
    _warm_imports()


@pytest.mark.parametrize("name", sorted(n for n in CASES if not CASES[n].node))
def test_bad_input_is_refused_in_one_line(name, tmp_path, warm):
    """The CLI cases; the node cases (a ROS node process each) are in test_bad_inputs_nodes."""
    folder = tmp_path / "case"
    folder.mkdir()
    assert_refused(CASES[name], folder, CLI, dict(os.environ))


def test_limit_option_raises_and_lowers_a_limit(tmp_path):
    """--limit NAME=VALUE (and MOTOFLEX_LIMIT_NAME) change the limit for one command."""
    _write(tmp_path, tube())
    base = CLI + ["components", "--component", str(tmp_path / TUBE), "--json"]
    assert subprocess.run(base, capture_output=True, timeout=60).returncode == 0
    lowered = subprocess.run(base + ["--limit", "dofs=100"], capture_output=True, text=True,
                             timeout=60)
    assert lowered.returncode == 2 and "126 DOFs" in lowered.stderr
    assert "--limit dofs=N" in lowered.stderr and "MOTOFLEX_LIMIT_DOFS" in lowered.stderr
    env = {**os.environ, "MOTOFLEX_LIMIT_DOFS": "100"}
    assert subprocess.run(base, capture_output=True, timeout=60, env=env).returncode == 2
    many = CLI + ["eig", "--vehicle", "whipple_benchmark", "--range-kmh", "10", "11", "--step-kmh",
                  "1e-4", "--json"]
    refused = subprocess.run(many, capture_output=True, text=True, timeout=60)
    assert refused.returncode == 2 and "10,001 speeds" in refused.stderr
    raised = subprocess.run(many + ["--limit", "speeds=20000"], capture_output=True, timeout=120)
    assert raised.returncode == 0, raised.stderr


def test_identify_out_onto_an_existing_file_needs_force(tmp_path):
    out = tmp_path / "results.json"
    out.write_text("{}\n")
    cmd = CLI + ["identify", "--component", "tube", "--out", str(out), "--json"]
    refused = subprocess.run(cmd, capture_output=True, text=True, timeout=60)
    assert refused.returncode == 2 and "--force" in refused.stderr
    assert "Traceback" not in refused.stderr and out.read_text() == "{}\n"
    forced = subprocess.run(cmd + ["--force"], capture_output=True, text=True, timeout=120)
    assert forced.returncode == 0, forced.stderr
    assert '"tube"' in out.read_text()


@pytest.mark.parametrize("argv", [["replay", "BAG", "--identify", "OUT.json"],
                                  ["rerun", "BAG", "--out", "OUT.rrd"]])
def test_other_outputs_onto_an_existing_file_need_force(tmp_path, argv):
    (tmp_path / "BAG").mkdir()
    out = tmp_path / argv[-1]
    out.write_text("keep")
    argv = [str(tmp_path / a) if a in ("BAG", out.name) else a for a in argv]
    result = subprocess.run(CLI + argv, capture_output=True, text=True, timeout=30)
    assert result.returncode == 2 and "exists; give --force" in result.stderr, result.stderr
    assert out.read_text() == "keep"


def test_failed_campaign_leaves_no_temporary_folder_and_keeps_its_logs(tmp_path, monkeypatch):
    """Each campaign left a motoflex_campaign_* folder in the temp directory: it is removed,
    also on failure, when the failed run's logs are kept in its bag folder."""
    import tempfile

    from motoflex_ros.launcher import campaign_graph
    from motoflex_ros.launcher.run_failures import RunFailed
    temp = tmp_path / "tmp"
    temp.mkdir()
    monkeypatch.setattr(tempfile, "tempdir", str(temp))
    seen = []

    def failing_run(specs, pacer, duration, work_dir, **kw):
        seen.append(Path(work_dir))
        (Path(work_dir) / "log").mkdir()
        (Path(work_dir) / "log" / "identification.log").write_text("boom\n")
        raise RunFailed(f"node 'identification' died; its log: "
                        f"{Path(work_dir) / 'log' / 'identification.log'}")

    monkeypatch.setattr(campaign_graph, "run_graph", failing_run)
    monkeypatch.setattr(campaign_graph, "planned_run", lambda *a: (1.0, 1))
    bag = tmp_path / "bag"
    with pytest.raises(RunFailed) as info:
        campaign_graph.run_campaign_graph(["tube"], bag)
    assert seen and seen[0].parent == temp and seen[0].name.startswith("motoflex_campaign_")
    assert list(temp.iterdir()) == []
    kept = bag / "log" / "identification.log"
    assert kept.read_text() == "boom\n" and str(kept) in str(info.value)


def test_successful_run_folder_is_removed(tmp_path, monkeypatch):
    import tempfile

    from motoflex_ros.launcher.run import work_folder
    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))
    with work_folder("motoflex_run_") as folder:
        (folder / "log").mkdir()
        assert folder.parent == tmp_path
    assert list(tmp_path.iterdir()) == []
    given = tmp_path / "mine"
    given.mkdir()
    with work_folder("motoflex_run_", given) as folder:
        assert folder == given
    assert given.is_dir()   # a folder the caller gave is the caller's
