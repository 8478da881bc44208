"""``--use FILE``: the engineer's own component takes its role in the motorcycle (issue 15).

Round trip: the shipped frame exported as a pre-reduced superelement (``components --export``)
and put back with ``--use`` gives the same flexible and lumped motorcycles as the shipped frame
(same reduced model, so the same bench identification and the same superelement) to 1e-9. Bad
input: a missing file, a component that takes no role, two files for one role.
"""
import json
import shutil

import numpy as np
import pytest
import scipy.io

from motoflex_ros.cli.main import main
from motoflex_ros.config import config_path
from motoflex_ros.formats.component_file import load_component
from motoflex_ros.study.identified_variants import build_variant
from motoflex_ros.vehicle.linearize import linearize
from motoflex_ros.vehicle.model import load_vehicle

SPEEDS = ["60", "150"]


@pytest.fixture(scope="module")
def exported_frame(tmp_path_factory):
    folder = tmp_path_factory.mktemp("export")
    assert main(["components", "--component", "frame", "--export", str(folder)]) == 0
    return folder / "frame.yaml"


def _eig(capsys, *extra):
    assert main(["eig", "--vehicle", "touring", "--speeds-kmh", *SPEEDS, "--json",
                 *extra]) == 0
    return json.loads(capsys.readouterr().out)


def _eigenvalues(doc):
    return [np.array([complex(*p) for p in pairs]) for pairs in doc["eigenvalues"]]


def _assert_same_spectrum(got, want, rtol=1e-9):
    """Each eigenvalue of ``got`` has one of ``want`` within rtol of the largest (both ways:
    a nearest-neighbour match, no ordering of conjugate or degenerate pairs assumed)."""
    tol = rtol * np.max(np.abs(want))
    assert len(got) == len(want)
    distance = np.abs(got[:, None] - want[None, :])
    assert distance.min(axis=1).max() < tol and distance.min(axis=0).max() < tol


@pytest.mark.parametrize("flex", ["flexible", "static"])
def test_use_puts_the_file_in_the_motorcycle(exported_frame, capsys, flex):
    ours = _eig(capsys, "--flex", flex, "--component", "frame", "--use", str(exported_frame))
    shipped = _eig(capsys, "--flex", flex, "--component", "frame")
    assert ours["component_files"] == {"frame": str(exported_frame)}
    assert shipped["component_files"] == {}
    for a, b in zip(_eigenvalues(ours), _eigenvalues(shipped)):
        _assert_same_spectrum(a, b)
    for mode in ("weave", "wobble"):
        assert np.allclose(ours["modes"][mode], shipped["modes"][mode], rtol=1e-9, atol=0)


def test_use_of_a_stiffer_frame_moves_wobble_as_the_core_says(exported_frame, capsys, tmp_path):
    """The file is what the motorcycle gets: the exported frame made 4 x stiffer moves the
    wobble, and the CLI's eigenvalues are the core's of that file's flexible motorcycle."""
    for name in ("frame.yaml", "frame_M.mtx"):
        shutil.copy(exported_frame.parent / name, tmp_path / name)
    stiffness = scipy.io.mmread(exported_frame.parent / "frame_K.mtx")
    scipy.io.mmwrite(tmp_path / "frame_K.mtx", 4.0 * np.asarray(stiffness), symmetry="symmetric")
    stiff = _eig(capsys, "--flex", "flexible", "--component", "frame", "--use",
                 str(tmp_path / "frame.yaml"))
    shipped = _eig(capsys, "--flex", "flexible", "--component", "frame")
    wobble = [complex(*p) for p in stiff["modes"]["wobble"]]
    assert max(abs(a - complex(*b)) for a, b in zip(wobble, shipped["modes"]["wobble"])) > 0.05
    frame = load_component(str(tmp_path / "frame.yaml"))
    lin = linearize(build_variant(load_vehicle(config_path("vehicles", "touring")), "flexible",
                                  ["frame"], {}, {"frame": frame}))
    for v, got in zip(stiff["speeds_mps"], _eigenvalues(stiff)):
        _assert_same_spectrum(got, lin.eigenvalues(v))


def test_use_of_a_component_not_made_flexible_is_not_reported(exported_frame, capsys):
    doc = _eig(capsys, "--flex", "flexible", "--component", "swingarm", "--use",
               str(exported_frame))
    assert doc["component_files"] == {}


@pytest.mark.parametrize("use, words", [
    (["no/such/frame.yaml"], ["--use", "no/such/frame.yaml", "is not a file"]),
    ([str(config_path("components", "tube"))], ["tube.yaml", "'tube' takes no role",
                                                "frame, front_assembly, swingarm"]),
])
def test_use_refuses_what_takes_no_role(capsys, use, words):
    args = ["eig", "--vehicle", "touring", "--speeds-kmh", "60", "--flex", "flexible"]
    for path in use:
        args += ["--use", path]
    assert main(args) != 0
    err = capsys.readouterr().err
    assert all(w in err for w in words), err


def test_use_refuses_two_files_for_one_role(exported_frame, capsys):
    assert main(["study", "accuracy", "--use", str(exported_frame), "--use",
                 str(config_path("components", "frame"))]) != 0
    err = capsys.readouterr().err
    assert "two files for the frame" in err and str(exported_frame) in err, err
