"""Bad protocol files give a clear error naming the file and key, and a non-zero exit."""
import copy
import functools

import pytest
import yaml

from motoflex_ros.bench.campaign import setup_campaign
from motoflex_ros.bench.protocols import load_protocol
from motoflex_ros.cli.main import main
from motoflex_ros.config import config_path, load_yaml
from motoflex_ros.errors import ConfigError, ProtocolError

BASE = load_yaml(config_path("protocols", "swingarm"))


@functools.lru_cache(maxsize=1)
def first_hz():
    """First torsion/bending eigenfrequency of the swingarm [Hz] (from its reduced model)."""
    from motoflex_ros.bench.modes import clamped_modes
    from motoflex_ros.structures.components import load_component
    return clamped_modes(load_component("swingarm").clamped_reduced()).first_lateral().f_hz


def protocol_file(tmp_path, edit):
    data = copy.deepcopy(BASE)
    edit(data)
    path = tmp_path / "bad.yaml"
    path.write_text(yaml.safe_dump(data))
    return path


def set_key(*keys, value):
    def edit(data):
        node = data
        for k in keys[:-1]:
            node = node[k]
        node[keys[-1]] = value
    return edit


CONFIG_ERRORS = [
    (set_key("static", "force_n", value=0.0), "static.force_n"),
    (set_key("static", "force_n", value=-100.0), "static.force_n"),
    (set_key("sweep", "amplitude_n", value=0), "sweep.amplitude_n"),
    (lambda d: d["harmonic"]["tests"][0].update(amplitude_n=-5.0),
     "harmonic.tests[0].amplitude_n"),
    (lambda d: d["harmonic"]["tests"][0].update(frequency="second wobble"),
     "harmonic.tests[0].frequency"),
    (set_key("harmonic", "band_angle_rad", value=0.0), "harmonic.band_angle_rad"),
    (set_key("harmonic", "band_length_m", value=0.0), "harmonic.band_length_m"),
    (set_key("sweep", "end_below_first_hz", value=0.0), "sweep.end_below_first_hz"),
    (set_key("sensor", "noise_m", value=-1e-6), "sensor.noise_m"),
    (set_key("static", "hold_time", value=1.0), "static.hold_time"),
]


@pytest.mark.parametrize("edit, key", CONFIG_ERRORS)
def test_bad_protocol_value_names_file_and_key(tmp_path, edit, key):
    path = protocol_file(tmp_path, edit)
    with pytest.raises(ConfigError) as err:
        load_protocol(str(path))
    assert err.value.key == key
    assert str(path) in str(err.value)


PROTOCOL_ERRORS = [
    (lambda d: d["harmonic"]["tests"][0].update(frequency=3000.0), "Nyquist"),
    (lambda d: (d["sensor"].update(max_rate_hz=400.0),                # torsion at 237 Hz
                d["static"].update(sample_rate_hz=400.0)), "Nyquist"),
    (lambda d: (d["sweep"].pop("end_below_first_hz"),
                d["sweep"].update(end_hz=first_hz() + 1.0)), "not below the first"),
    (lambda d: d["sweep"].update(end_below_first_hz=first_hz() - 0.5), "below its start"),
    (set_key("static", "ramp_time_s", value=0.02), "ramp would excite"),
    (set_key("static", "force_n", value=1e6), "small and linear"),
    (set_key("static", "hold_time_s", value=0.001), "fewer than 10 samples"),
    (set_key("sweep", "amplitude_n", value=2e5), "small and linear"),
]


@pytest.mark.parametrize("edit, words", PROTOCOL_ERRORS)
def test_protocol_that_cannot_run_is_rejected(tmp_path, edit, words):
    path = protocol_file(tmp_path, edit)
    with pytest.raises(ProtocolError, match=words):
        setup_campaign("swingarm", str(path))


@pytest.mark.parametrize("edit, words", [(CONFIG_ERRORS[0][0], "static.force_n"),
                                         (PROTOCOL_ERRORS[0][0], "Nyquist"),
                                         (PROTOCOL_ERRORS[2][0], "not below the first")])
def test_identify_command_exits_non_zero_without_output(tmp_path, capsys, edit, words):
    path = protocol_file(tmp_path, edit)
    out = tmp_path / "result.json"
    code = main(["identify", "--component", "swingarm", "--protocol", str(path),
                 "--out", str(out), "--json"])
    captured = capsys.readouterr()
    assert code == 2
    assert words in captured.err
    assert captured.out == ""
    assert not out.exists()


def test_shipped_protocols_load():
    for name in ("default", "frame", "front_assembly", "swingarm"):
        assert load_protocol(name).static.force_n > 0
