"""Pre-reduced superelements (issue 15): a reduction made elsewhere, given as its reduced
matrices (Matrix Market) and interface DOF map, enters the bench and the vehicle like our own.

Round trip: reduce here, export (motoflex_ros.formats.superelement_file), re-import: the
bench results (the whole campaign, exact sensor) and the vehicle's superelement and flexible
weave/wobble equal to 1e-9. For a mesh component (an L bracket of hexahedra) and for the
shipped swingarm (two clamps), placed in the touring motorcycle.
"""
import json

import numpy as np
import pytest
from hostile import run_motoflex

from motoflex_ros.bench.offline_campaign import run_campaign, setup_campaign, with_sensor
from motoflex_ros.config import config_path
from motoflex_ros.errors import ConfigError
from motoflex_ros.formats.component_file import load_component
from motoflex_ros.formats.mesh_examples import write_bracket_component
from motoflex_ros.formats.superelement_file import export_superelement
from motoflex_ros.vehicle import lumped
from motoflex_ros.vehicle.linearize import linearize
from motoflex_ros.vehicle.model import load_vehicle
from motoflex_ros.vehicle.modes import modal_sweep
from motoflex_ros.vehicle.superelement import superelement_of
from motoflex_ros.vehicle.variants import flexible_vehicle


def flat(tree, prefix=""):
    """{dotted key: number} of a results document (lists by index)."""
    out = {}
    items = tree.items() if isinstance(tree, dict) else enumerate(tree)
    for key, value in items:
        name = f"{prefix}.{key}" if prefix else str(key)
        if isinstance(value, (dict, list)):
            out.update(flat(value, name))
        elif isinstance(value, (int, float)) and not isinstance(value, bool):
            out[name] = float(value)
    return out


@pytest.fixture(scope="module", params=["bracket", "swingarm"])
def round_trip(request, tmp_path_factory):
    """(original component, re-imported superelement component)."""
    tmp = tmp_path_factory.mktemp("se")
    spec = (str(write_bracket_component(tmp / "mesh")) if request.param == "bracket"
            else "swingarm")
    original = load_component(spec)
    imported = load_component(str(export_superelement(original, tmp / "export")))
    return original, imported


def test_reduced_models_equal(round_trip):
    original, imported = round_trip
    a, b = original.clamped_reduced(), imported.clamped_reduced()
    assert imported.kind == "superelement" and imported.name == original.name
    for key in ("M", "K", "C"):
        x, y = getattr(a, key), getattr(b, key)
        assert np.abs(x - y).max() <= 1e-12 * np.abs(x).max(), key
    np.testing.assert_allclose(b.frequencies_hz, a.frequencies_hz, rtol=1e-12)
    # the same labels, but for 'local' modes (a part vibrating on its own): telling them needs
    # the interior's motion, which a superelement does not carry
    assert [lab for lab in a.mode_labels if lab != "local"] == [
        lab for lab, other in zip(b.mode_labels, a.mode_labels) if other != "local"]
    for label in ("torsion", "bending"):
        assert a.first_mode(label) == b.first_mode(label)
    np.testing.assert_allclose(imported.q0, original.q0, rtol=0, atol=1e-15)


def test_bench_results_equal(round_trip):
    """The whole bench campaign (static, harmonic, sweep, decay; exact sensor) identifies the
    same l, beta, b, k, c, J, k_t, k_b, poles on the superelement as on its original."""
    results = []
    for comp in round_trip:
        setup = with_sensor(setup_campaign(comp), noise_m=0.0, resolution_m=0.0)
        results.append(flat(run_campaign(setup).identification.to_dict()))
    assert results[0].keys() == results[1].keys()
    for key, value in results[0].items():
        assert results[1][key] == pytest.approx(value, rel=1e-9, abs=1e-12), key


def test_vehicle_results_equal(round_trip):
    """The superelement the vehicle gets (M, K, C and the rigid-motion coupling M_xR) equals
    the original's to 1e-9; for the swingarm, the flexible touring motorcycle's weave and wobble
    too."""
    original, imported = round_trip
    parent = lumped.SUPERELEMENT_PARENT.get(original.name, "frame")
    ours, theirs = superelement_of(original, parent), superelement_of(imported, parent)
    for key in ("M", "K", "C", "M_xR"):
        x, y = getattr(ours, key), getattr(theirs, key)
        assert np.abs(x - y).max() <= 1e-9 * np.abs(x).max(), key
    np.testing.assert_allclose(theirs.end_point, ours.end_point, atol=1e-15)
    if original.name != "swingarm":
        return
    vehicle = load_vehicle(config_path("vehicles", "touring"))
    speeds = np.array([60.0, 140.0]) / 3.6
    modes = []
    for se in (ours, theirs):
        sweep = modal_sweep(linearize(flexible_vehicle(vehicle, {"swingarm": se})), speeds)
        modes.append(np.concatenate([sweep.modes["weave"], sweep.modes["wobble"]]))
    np.testing.assert_allclose(modes[1], modes[0], rtol=1e-9)


def test_export_from_the_command_line(tmp_path):
    """``motoflex components --component X --export DIR`` writes the superelement, and the
    exported file goes through ``components --json`` with the original's numbers."""
    out = run_motoflex(["components", "--component", "tube", "--export", tmp_path, "--json"])
    assert out.returncode == 0, out.stderr
    exported = tmp_path / "tube.yaml"
    again = run_motoflex(["components", "--component", exported, "--json"])
    assert again.returncode == 0, again.stderr
    a, b = json.loads(out.stdout)["tube"], json.loads(again.stdout)["tube"]
    for key in ("k_static", "f_bending_hz", "f_torsion_hz"):
        assert b[key] == pytest.approx(a[key], rel=1e-9), key


def test_superelement_with_moving_bodies_is_refused_in_the_flexible_motorcycle(tmp_path):
    """A swingarm superelement has no members to say which of its nodes ride on the torque
    strut and the wheel carrier (vehicle.lumped.SUPERELEMENT_FOLLOWS): ``eig --flex flexible``
    refuses it in one line naming the file, no traceback (it crashed with an AttributeError)."""
    exported = export_superelement(load_component("swingarm"), tmp_path)
    out = run_motoflex(["eig", "--vehicle", "touring", "--speeds-kmh", "100", "--flex",
                        "flexible", "--component", "swingarm", "--use", exported])
    assert out.returncode == 2, out.stderr
    assert "Traceback" not in out.stderr
    error = out.stderr.splitlines()[-1]
    assert str(exported) in error and "torque_strut, wheel_carrier" in error, out.stderr
    assert "beam or mesh model" in error


def test_bad_superelement_files_are_refused(tmp_path):
    """Unsymmetric or non-square matrices, rows out of range or shared, an unknown clamp: a
    ConfigError naming the file and the key."""
    path = export_superelement(load_component("tube"), tmp_path)
    text = path.read_text()
    cases = [("row: 6", "row: 3", "superelement.interface.free_end.row"),
             ("row: 6", "row: 600", "superelement.interface.free_end.row"),
             ("- clamp", "- pivot", "superelement.clamps[0]")]
    for old, new, key in cases:
        bad = tmp_path / "bad.yaml"
        bad.write_text(text.replace(old, new, 1))
        with pytest.raises(ConfigError) as info:
            load_component(str(bad))
        assert info.value.key == key and "bad.yaml" in str(info.value), str(info.value)
    from scipy.io import mmread, mmwrite
    k_file = tmp_path / "tube_K.mtx"
    k = mmread(str(k_file)).toarray() if hasattr(mmread(str(k_file)), "toarray") else \
        np.asarray(mmread(str(k_file)))
    for bad_matrix, words in ((k + np.triu(np.ones_like(k), 1) * abs(k).max(), "symmetric"),
                              (k[:, :-1], "square")):
        mmwrite(str(k_file), bad_matrix)
        with pytest.raises(ConfigError) as info:
            load_component(str(path))
        assert info.value.key == "superelement.stiffness" and words in str(info.value)
