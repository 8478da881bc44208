"""Bad protocol files give a clear error naming the file and key, and a non-zero exit."""
import copy
import functools

import pytest
import yaml

from motoflex_ros.bench.offline_campaign import (
    only_tests,
    run_campaign,
    setup_campaign,
    with_sensor,
)
from motoflex_ros.bench.protocols import MIN_MARKER_SPREAD_M, load_protocol
from motoflex_ros.cli.main import main
from motoflex_ros.config import config_path, load_yaml
from motoflex_ros.errors import ConfigError, ProtocolError
from motoflex_ros.formats.component_file import load_component

BASE = load_yaml(config_path("protocols", "swingarm"))


@functools.lru_cache(maxsize=1)
def first_hz():
    """First torsion/bending eigenfrequency of the swingarm [Hz] (from its reduced model)."""
    from motoflex_ros.bench.clamped_modes import clamped_modes
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
    (set_key("sensor", "noise_m", value=2e-3), "sensor.noise_m"),     # above MAX_NOISE_M 1 mm
    # the identification needs harmonic tests named torsion and bending...
    (lambda d: d["harmonic"]["tests"][1].update(name="foo"), "harmonic.tests"),
    (lambda d: d["harmonic"].pop("tests"), "harmonic.tests"),
    (set_key("harmonic", "tests", value=[]), "harmonic.tests"),
    # ... and no test may take the name of another test or of a result key
    (lambda d: d["harmonic"]["tests"][0].update(name="static"), "harmonic.tests[0].name"),
    (lambda d: d["harmonic"]["tests"].append(dict(d["harmonic"]["tests"][0], name="static")),
     "harmonic.tests[2].name"),
    (lambda d: d["harmonic"]["tests"].append(dict(d["harmonic"]["tests"][0], name="k_t")),
     "harmonic.tests[2].name"),
    (lambda d: d["harmonic"]["tests"].append(dict(d["harmonic"]["tests"][0], name="sweep_00")),
     "harmonic.tests[2].name"),
    (lambda d: d["harmonic"]["tests"].append(dict(d["harmonic"]["tests"][0], name="decay")),
     "harmonic.tests[2].name"),
    # markers that do not span a plane leave the rotation about their line unmeasured
    (set_key("sensor", "markers", value=[[0, 0, 0], [0.1, 0, 0], [0.2, 0, 0]]),
     "sensor.markers"),
    (set_key("sensor", "markers", value=[[0.1, 0.2, 0.3]] * 4), "sensor.markers"),
    (set_key("sensor", "markers", value=[[0, 0, 0], [0.1, 0, 0], [0.2, 0.5e-3, 0]]),
     "sensor.markers"),
]


@pytest.mark.parametrize("edit, key", CONFIG_ERRORS)
def test_bad_protocol_value_names_file_and_key(tmp_path, edit, key):
    path = protocol_file(tmp_path, edit)
    with pytest.raises(ConfigError) as err:
        load_protocol(str(path))
    assert err.value.key == key
    assert str(path) in str(err.value)


def test_planar_and_extra_tests_are_allowed(tmp_path):
    """Three markers in a plane fix every rotation (here: a spread 3 * 0.816 MIN_MARKER_SPREAD_M
    across their line); a harmonic test of another name is an extra test."""
    def edit(data):
        data["sensor"]["markers"] = [[0, 0, 0], [0.1, 0, 0], [0.2, 3 * MIN_MARKER_SPREAD_M, 0]]
        data["harmonic"]["tests"].append(dict(data["harmonic"]["tests"][0], name="foo"))
    protocol = load_protocol(str(protocol_file(tmp_path, edit)))
    assert [t.name for t in protocol.harmonic_tests] == ["torsion", "bending", "foo"]
    assert len(protocol.sensor.markers) == 3


PROTOCOL_ERRORS = [
    (lambda d: d["harmonic"]["tests"][0].update(frequency=3000.0), "Nyquist",
     "harmonic.tests[0].frequency"),
    (lambda d: (d["sensor"].update(max_rate_hz=400.0),                # torsion at 237 Hz
                d["static"].update(sample_rate_hz=400.0)), "Nyquist",
     "harmonic.tests[0].frequency"),
    (lambda d: (d["sweep"].pop("end_below_first_hz"),
                d["sweep"].update(end_hz=first_hz() + 1.0)), "not below the first",
     "sweep.end_hz"),
    (lambda d: d["sweep"].update(end_below_first_hz=first_hz() - 0.5), "below its start",
     "sweep.end_below_first_hz"),
    (set_key("static", "ramp_time_s", value=0.02), "ramp would excite", "static.ramp_time_s"),
    (set_key("static", "force_n", value=1e6), "small and linear", "static.force_n"),
    (set_key("static", "hold_time_s", value=0.001), "fewer than 10 samples",
     "static.hold_time_s"),
    (set_key("sweep", "amplitude_n", value=2e5), "small and linear", "sweep.amplitude_n"),
    (set_key("modal", "preload_n", value=1e6), "small and linear", "modal.preload_n"),
]


@pytest.mark.parametrize("edit, words, key", PROTOCOL_ERRORS)
def test_protocol_that_cannot_run_names_file_and_key(tmp_path, edit, words, key):
    path = protocol_file(tmp_path, edit)
    with pytest.raises(ProtocolError, match=words) as err:
        setup_campaign(load_component("swingarm"), str(path))
    assert str(err.value).startswith(f"{path}: key '{key}': ")


@pytest.mark.parametrize("edit, words", [
    (CONFIG_ERRORS[0][0], "static.force_n"),
    (PROTOCOL_ERRORS[0][0], "Nyquist"),
    (PROTOCOL_ERRORS[2][0], "not below the first"),
    (lambda d: d["harmonic"]["tests"][0].update(name="twist"), "'harmonic.tests': no test named "
                                                               "torsion"),
    (lambda d: d["harmonic"]["tests"][1].update(name="static"), "'harmonic.tests[1].name'")])
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


def test_non_positive_stiffness_is_refused_not_reported():
    """A sensor noise far above the deflections (1 m, once allowed by --noise) gave the swingarm
    a static k of -811 N m/rad with exit 0; the identification now refuses it."""
    setup = only_tests(with_sensor(setup_campaign(load_component("swingarm")), noise_m=1.0),
                       ("static", "torsion", "bending"))
    with pytest.raises(ProtocolError, match=r"swingarm: the static model gives k = -\d.* not a "
                                            r"positive stiffness"):
        run_campaign(setup, seed=0)


def test_reserved_names_cover_every_result_key(tmp_path):
    """The names a test may not take are exactly the keys the results hold besides the tests':
    a campaign with an extra test 'foo' gives static, torsion, bending, foo and RESULT_KEYS."""
    from motoflex_ros.identify.results import MODEL_TESTS, RESULT_KEYS

    def edit(data):
        data["harmonic"]["tests"].append(dict(data["harmonic"]["tests"][0], name="foo"))
    setup = setup_campaign(load_component("swingarm"), str(protocol_file(tmp_path, edit)),
                           noise_m=0.0)
    run = run_campaign(only_tests(setup, MODEL_TESTS + ("foo",)))
    assert sorted(run.identification.to_dict()) == sorted(MODEL_TESTS + RESULT_KEYS + ("foo",))
