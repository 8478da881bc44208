"""The three motorcycle components against the paper, mode labels, hard points, bad input.

Published values: Passigato et al. (2023), Table 1 (first torsion/bending eigenfrequencies:
frame 74/93 Hz, front assembly 28/79 Hz, swingarm 321/112 Hz) and Table 2 (k about the static
axis: 1.03e6, 1.06e4, 1.33e5 N m/rad). Tolerances are the issue's: 5 % and 10 %.
"""
import copy

import numpy as np
import pytest
import yaml
from hostile import run_motoflex

from motoflex_ros.cli.main import main
from motoflex_ros.config import config_path
from motoflex_ros.errors import ConfigError
from motoflex_ros.formats.component_file import load_component
from motoflex_ros.structures.component_summary import summarize
from motoflex_ros.structures.paper_tables import (
    paper_table1_eigenfrequencies,
    paper_table2_stiffness,
)

NAMES = ("frame", "front_assembly", "swingarm")
FIRST_MODE = {"frame": "torsion", "front_assembly": "torsion", "swingarm": "bending"}


@pytest.fixture(scope="module")
def reduced():
    comps = {n: load_component(n) for n in NAMES}
    return {n: (c, c.clamped_reduced()) for n, c in comps.items()}


@pytest.mark.parametrize("name", NAMES)
def test_table1_eigenfrequencies_published(name, reduced):
    comp, red = reduced[name]
    table = paper_table1_eigenfrequencies()[name]
    assert red.frequency("torsion") == pytest.approx(table["torsion"], rel=0.05)
    assert red.frequency("bending") == pytest.approx(table["bending"], rel=0.05)


@pytest.mark.parametrize("name", NAMES)
def test_table1_mode_order_published(name, reduced):
    """Frame and front assembly: torsion is the first mode; swingarm: bending is."""
    _, red = reduced[name]
    assert red.mode_labels[0] == FIRST_MODE[name]


@pytest.mark.parametrize("name", NAMES)
def test_table2_static_stiffness_published(name, reduced):
    comp, red = reduced[name]
    s = summarize(comp, red)
    assert s.k_static == pytest.approx(paper_table2_stiffness()[name]["k"], rel=0.10)


def test_static_stiffness_independent_of_load_magnitude(reduced):
    _, red = reduced["frame"]
    assert red.static_lateral(10.0).k == pytest.approx(red.static_lateral(1000.0).k, rel=1e-6)


def test_mode_labels_of_straight_tube_analytic():
    """A straight tube: the lateral bending mode is 'bending', the vertical one 'in_plane', the
    twist 'torsion' (axis along O-q0), whatever their order."""
    red = load_component("tube").clamped_reduced(f_max_hz=1e5)
    labels = list(red.mode_labels)
    assert labels[:2] in (["bending", "in_plane"], ["in_plane", "bending"])
    i = red.first_mode("torsion")
    assert red.frequencies_hz[i] == pytest.approx(1338.4, rel=5e-3)   # (1/4L) sqrt(G/rho)


def test_interface_points_meet_hardpoints():
    """Hard points (docs/hardpoints.md, vehicle frame, m) within 1 mm."""
    expect = {"frame": {"steering_head": (1.2216, 0.780)},
              "front_assembly": {"steering_head": (1.2216, 0.780), "front_axle": (1.485, 0.300),
                                 "arm_pivot": (1.030, 0.420)},
              "swingarm": {"swingarm_pivot": (0.600, 0.360), "rear_axle": (0.000, 0.315)}}
    for name, points in expect.items():
        found = load_component(name).interface_points()
        for point, (x, z) in points.items():
            assert np.allclose(found[point], [x, 0.0, z], atol=1e-3), (name, point)


def test_masses_plausible_for_the_real_parts():
    """Structure + attached parts: TUM data 9.3 + 6.5 kg fork, ~8 kg swingarm (2d)."""
    def mass(name):
        asm = load_component(name).assembled()
        e = np.zeros(asm.M.shape[0])
        x_dofs = asm.free_index[0::6]
        e[x_dofs[x_dofs >= 0]] = 1.0    # rigid x translation of every independent node
        return float(e @ (asm.M @ e))
    assert 10.0 < mass("front_assembly") < 20.0
    assert 7.0 < mass("swingarm") < 16.0
    assert 25.0 < mass("frame") < 60.0


def _tube():
    return yaml.safe_load(config_path("components", "tube").read_text())


def _frame():
    return yaml.safe_load(config_path("components", "frame").read_text())


def _set(data, path, value):
    out = copy.deepcopy(data)
    keys = path.split(".")
    node = out
    for k in keys[:-1]:
        node = node[int(k)] if isinstance(node, list) else node[k]
    last = keys[-1]
    if value is _DELETE:
        del node[last]
    else:
        node[int(last) if isinstance(node, list) else last] = value
    return out


_DELETE = object()
BAD = [
    ("unknown key", _tube, "colour", "red", "colour"),
    ("missing key", _tube, "material", _DELETE, "material"),
    ("missing nested key", _tube, "tube.length", _DELETE, "tube.length"),
    ("wrong type", _tube, "elements", "twenty", "elements"),
    ("not a whole number", _tube, "elements", 2.5, "elements"),
    ("zero modulus", _tube, "material.E", 0.0, "material.E"),
    ("negative shear modulus", _tube, "material.G", -8.1e10, "material.G"),
    ("negative density", _tube, "material.rho", -7850.0, "material.rho"),
    ("zero length", _tube, "tube.length", 0.0, "tube.length"),
    ("NaN", _tube, "tube.outer_diameter", float("nan"), "tube.outer_diameter"),
    ("angle out of range", _tube, "tube.pitch_deg", 120.0, "tube.pitch_deg"),
    ("wall thicker than radius", _tube, "tube.wall_thickness", 0.03, "tube.wall_thickness"),
    ("unknown node", _frame, "members.0.to", "nowhere", "members[0].to"),
    ("negative spring", _frame, "springs.0.k_translation.1", -1.0,
     "springs[0].k_translation[1]"),
    ("zero mass", _frame, "rigid_parts.tank.mass", 0.0, "rigid_parts.tank.mass"),
    ("unknown shape", _frame, "sections.spar.shape", "hexagon", "sections.spar.shape"),
    ("unknown section", _frame, "members.1.section", "girder", "members[1].section"),
]


@pytest.mark.parametrize("what, base, path, value, key", BAD, ids=[b[0] for b in BAD])
def test_bad_component_config_names_key(what, base, path, value, key, tmp_path, capsys):
    bad = tmp_path / "bad.yaml"
    bad.write_text(yaml.safe_dump(_set(base(), path, value)))
    with pytest.raises(ConfigError) as err:
        load_component(str(bad))
    assert f"'{key}'" in str(err.value) and str(bad) in str(err.value)
    assert main(["components", "--component", str(bad)]) != 0
    printed = capsys.readouterr().err
    assert key in printed and "Traceback" not in printed


def test_bad_component_cli_exit_without_traceback(tmp_path):
    bad = tmp_path / "bad.yaml"
    bad.write_text(yaml.safe_dump(_set(_tube(), "material.E", -1.0)))
    p = run_motoflex(["components", "--component", bad])
    assert p.returncode != 0
    assert "material.E" in p.stderr and "Traceback" not in p.stderr


def test_components_json_shape(capsys):
    import json
    assert main(["components", "--component", "front_assembly", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    entry = data["front_assembly"]
    for key in ("f_torsion_hz", "f_bending_hz", "k_static", "dofs", "modes"):
        assert isinstance(entry[key], (int, float))


def test_components_plot_writes_png(tmp_path, capsys):
    assert main(["components", "--component", "swingarm", "--plot", str(tmp_path)]) == 0
    png = tmp_path / "swingarm.png"
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert not list(tmp_path.glob(".*.tmp"))
