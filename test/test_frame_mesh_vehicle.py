"""The shipped solid frame (config/components/mesh/frame_mesh.yaml, 106k DOFs after the spiders)
through the whole chain, in the frame's role (issue 15): bench identification, the vehicle
(flexible and lumped) and the accuracy study from the command line with ``--use``.

Independent checks: the CLI's static hinge is the core's identification of the mesh frame
(same seed; and not the shipped beam frame's); the flexible motorcycle with the mesh frame
converges on the rigid motorcycle as its stiffness grows (x 1e2, x 1e4); its Craig-Bampton
reduction is made once for all of it (the on-disk cache, test_reduction_cache).
"""
import contextlib
import io
import json
from dataclasses import replace

import numpy as np
import pytest

from motoflex_ros.bench.offline_campaign import identify_components
from motoflex_ros.cli.main import main
from motoflex_ros.config import config_path
from motoflex_ros.formats.component_file import load_component, load_components
from motoflex_ros.study.identified_variants import build_variant
from motoflex_ros.vehicle.linearize import linearize
from motoflex_ros.vehicle.model import load_vehicle
from motoflex_ros.vehicle.modes import modal_sweep

MESH = config_path("components", "mesh/frame_mesh")
SPEEDS = np.array([40.0, 120.0, 210.0]) / 3.6


@pytest.fixture(scope="module")
def mesh_frame():
    return load_component(str(MESH))


@pytest.fixture(scope="module")
def study(tmp_path_factory, mesh_frame):
    details = tmp_path_factory.mktemp("study") / "details.json"
    stream = io.StringIO()
    with contextlib.redirect_stdout(stream):
        code = main(["study", "accuracy", "--use", str(MESH), "--cases", "frame",
                     "--step-kmh", "10", "--details", str(details), "--json"])
    assert code == 0
    return json.loads(stream.getvalue()), json.loads(details.read_text())


def test_the_study_runs_on_the_mesh_frame(study):
    errors, _ = study
    assert list(errors) == ["frame"]
    for variant in ("state_of_the_art", "static", "torsion", "bending", "fitted"):
        values = errors["frame"][variant]
        assert all(np.isfinite(values[q]) and values[q] >= 0 for q in
                   ("weave_f", "weave_re", "wobble_f", "wobble_re")), variant


def test_the_static_hinge_is_the_mesh_frames(study, mesh_frame):
    _, details = study
    static = details["components"]["frame"]["fit"]["components"]["frame"]["static"]
    runs = identify_components([mesh_frame], seed=0)
    core = runs["frame"][1].identification.to_dict()["static"]
    for key in ("l", "beta", "k"):
        assert static[key] == pytest.approx(core[key], rel=1e-9), key
    shipped = identify_components(load_components(["frame"]),
                                  seed=0)["frame"][1].identification.to_dict()
    assert abs(static["k"] / shipped["static"]["k"] - 1.0) > 0.1


def test_mesh_frame_rigid_limit(mesh_frame):
    vehicle = load_vehicle(config_path("vehicles", "touring"))
    flexible = build_variant(vehicle, "flexible", ["frame"], {}, {"frame": mesh_frame})
    rigid = modal_sweep(linearize(vehicle), SPEEDS)
    gaps = []
    for factor in (1.0, 1e2, 1e4):
        model = replace(flexible, elements=tuple(e.scaled(factor) for e in flexible.elements))
        sweep = modal_sweep(linearize(model), SPEEDS)
        gaps.append(max(float(np.max(np.abs(np.asarray(sweep.modes[m])
                                             - np.asarray(rigid.modes[m]))
                                      / np.abs(np.asarray(rigid.modes[m]))))
                        for m in ("weave", "wobble")))
    assert gaps[0] > gaps[1] > gaps[2] and gaps[2] < 1e-3, gaps
