"""``motoflex eig``: JSON shape, numbers equal to the core, plots written."""
import json

import numpy as np

from motoflex_ros.cli.main import main
from motoflex_ros.config import config_path
from motoflex_ros.vehicle.linearize import linearize
from motoflex_ros.vehicle.model import load_vehicle


def test_eig_json_roundtrip_whipple(capsys):
    assert main(["eig", "--vehicle", str(config_path("vehicles", "whipple_benchmark")),
                 "--speeds-ms", "5", "10", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["speeds_mps"] == [5.0, 10.0]
    assert (doc["variant"], doc["components"]) == ("rigid", [])   # the model it is of
    assert doc["vehicle"] == str(config_path("vehicles", "whipple_benchmark"))
    lin = linearize(load_vehicle(config_path("vehicles", "whipple_benchmark")))
    for v, pairs in zip(doc["speeds_mps"], doc["eigenvalues"]):
        got = np.array([complex(*p) for p in pairs])
        assert sorted(np.round(got, 9), key=lambda z: (z.real, z.imag)) == sorted(
            np.round(lin.eigenvalues(v), 9), key=lambda z: (z.real, z.imag))
    weave = complex(*doc["modes"]["weave"][0])
    assert abs(weave - (-0.77534188219585 + 4.46486771378823j)) < 1e-9   # Meijaard 2007
    assert doc["modes"]["wobble"] == [None, None]   # a bicycle has no wobble


def test_eig_range_and_plot(tmp_path, capsys):
    assert main(["eig", "--vehicle", "touring", "--range-kmh", "40", "210", "--step-kmh", "85",
                 "--plot", str(tmp_path), "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert np.allclose(np.array(doc["speeds_mps"]) * 3.6, [40.0, 125.0, 210.0])
    assert all(len(doc["modes"][m]) == 3 for m in ("weave", "wobble", "capsize"))
    assert (tmp_path / "root_locus.png").stat().st_size > 1000
    assert (tmp_path / "weave_wobble.png").stat().st_size > 1000
