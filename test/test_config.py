"""Validation of YAML configuration: every failure names the file, the key and the range."""
import math

import pytest

from motoflex_ros.config import (
    Field,
    angle,
    config_path,
    load_config,
    number,
    positive,
    resolve_config,
    validate,
)
from motoflex_ros.errors import ConfigError

SPEC = Field("mapping", fields={
    "name": Field("str", choices=("tube", "frame")),
    "length": positive(),
    "pitch_deg": angle(-90.0, 90.0),
    "ratio": number(0.0, 1.0, open_high=True),
    "elements": Field("int", 1, 10000),
    "point": Field("vec3"),
    "nested": Field("mapping", fields={"E": positive()}),
    "flag": Field("bool", required=False, default=False),
})
GOOD = {"name": "tube", "length": 0.6, "pitch_deg": 10, "ratio": 0.5, "elements": 20,
        "point": [0, 0, 1], "nested": {"E": 2.1e11}}


def test_good_config_is_normalised():
    out = validate(GOOD, SPEC, "good.yaml")
    assert out["pitch_deg"] == 10.0 and isinstance(out["pitch_deg"], float)
    assert out["elements"] == 20 and isinstance(out["elements"], int)
    assert out["flag"] is False


BAD = [
    ({"length": -1.0}, "length", "(0, inf)"),
    ({"length": 0.0}, "length", "(0, inf)"),
    ({"length": math.nan}, "length", "finite"),
    ({"length": "long"}, "length", "expected a number"),
    ({"pitch_deg": 95.0}, "pitch_deg", "[-90, 90]"),
    ({"ratio": 1.0}, "ratio", "[0, 1)"),
    ({"elements": 2.5}, "elements", "whole number"),
    ({"name": "truss"}, "name", "tube, frame"),
    ({"point": [0, 1]}, "point", "3 numbers"),
    ({"nested": {"E": 2e11, "nu": 0.3}}, "nested.nu", "unknown key"),
    ({"nested": {}}, "nested.E", "missing"),
    ({"flag": "yes"}, "flag", "true or false"),
]


@pytest.mark.parametrize("change, key, allowed", BAD)
def test_bad_value_names_file_key_and_range(change, key, allowed):
    data = {**GOOD, **change}
    with pytest.raises(ConfigError) as info:
        validate(data, SPEC, "bad.yaml")
    message = str(info.value)
    assert "bad.yaml" in message and f"'{key}'" in message and allowed in message
    assert info.value.key == key


def test_missing_and_unknown_top_level_keys():
    with pytest.raises(ConfigError, match="'length': missing"):
        validate({k: v for k, v in GOOD.items() if k != "length"}, SPEC, "f.yaml")
    with pytest.raises(ConfigError, match="'colour': unknown key"):
        validate({**GOOD, "colour": "red"}, SPEC, "f.yaml")


def test_load_config_reports_missing_file_and_bad_yaml(tmp_path):
    with pytest.raises(ConfigError, match="file not found"):
        load_config(tmp_path / "nope.yaml", SPEC)
    broken = tmp_path / "broken.yaml"
    broken.write_text("a: [1, 2\n")
    with pytest.raises(ConfigError, match="not valid YAML"):
        load_config(broken, SPEC)
    empty = tmp_path / "empty.yaml"
    empty.write_text("")
    with pytest.raises(ConfigError, match="empty"):
        load_config(empty, SPEC)


def test_shipped_config_found_through_package_resources():
    path = config_path("components", "frame")
    assert path.parent.name == "components" and path.parent.parent.name == "config"
    with pytest.raises(ConfigError, match="no shipped components configuration"):
        resolve_config("components", "no_such_component")


def component_error(tmp_path, edit):
    """ConfigError of the shipped swingarm component YAML after ``edit`` (written to a file)."""
    import yaml

    from motoflex_ros.config import load_yaml
    from motoflex_ros.formats.component_file import load_component
    data = load_yaml(config_path("components", "swingarm"))
    edit(data)
    path = tmp_path / "bad_component.yaml"
    path.write_text(yaml.safe_dump(data))
    with pytest.raises(ConfigError) as info:
        load_component(str(path))
    assert str(path) in str(info.value)
    return info.value


@pytest.mark.parametrize("inertia", [[0.01, 0.01, 0.05], [0.3, 0.001, 0.001]])
def test_rigid_part_inertia_violates_triangle_inequality(tmp_path, inertia):
    """Principal moments of a rigid body satisfy I1 + I2 >= I3 (the vehicle loader's check)."""
    def edit(data):
        data["rigid_parts"]["final_drive"]["inertia"] = inertia
    err = component_error(tmp_path, edit)
    assert err.key == "rigid_parts.final_drive.inertia" and "triangle inequality" in str(err)


@pytest.mark.parametrize("edit", [
    lambda d: d["nodes"].update(orphan=[0.3, 0.3, 0.3]),
    lambda d: (d["nodes"].update(orphan=[0.3, 0.3, 0.3]),
               d["rigid_parts"]["final_drive"].update(node="orphan")),
])
def test_unconnected_node_is_named(tmp_path, edit):
    """A node no member, spring or rigid link uses made the interior stiffness singular with
    no file or node named; a rigid part on it adds mass, not stiffness."""
    err = component_error(tmp_path, edit)
    assert err.key == "nodes.orphan" and "not connected" in str(err)
