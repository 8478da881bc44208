"""One CLI style across the verbs (issue 16, point 8): repeatable list options, unit-named
flags, defaults stated in --help; the older forms keep working with a deprecation warning."""
import argparse
import json
import re

import numpy as np
import pytest

from motoflex_ros.cli.main import build_parser, main


def _leaf_parsers(parser, path=()):
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for name, sub in action.choices.items():
                yield from _leaf_parsers(sub, path + (name,))
            return
    yield path, parser


def test_every_default_is_stated_in_help():
    """Options that take a value state their default; a flag (no value: store_true,
    store_false) is off unless given and shows no "(default: True)" (issue 24, point 9)."""
    unstated, flags = [], []
    for path, parser in _leaf_parsers(build_parser()):
        for action in parser._actions:
            if not action.option_strings or action.help in (None, argparse.SUPPRESS):
                continue
            if action.nargs == 0:
                if re.search(r"\(default: (True|False)\)", action.help):
                    flags.append((" ".join(path), action.option_strings[0]))
                continue
            if action.default in (None, False, [], argparse.SUPPRESS):
                continue
            if "default" not in action.help.lower():
                unstated.append((" ".join(path), action.option_strings[0]))
    assert unstated == [] and flags == []


def test_list_options_are_repeatable_everywhere():
    """Every option taking component names is ``--component NAME`` (append)."""
    for path, parser in _leaf_parsers(build_parser()):
        for action in parser._actions:
            if "--component" in action.option_strings:
                assert isinstance(action, argparse._AppendAction), path


def test_speed_flags_name_their_unit():
    for path, parser in _leaf_parsers(build_parser()):
        for action in parser._actions:
            if action.help == argparse.SUPPRESS:
                continue
            for flag in action.option_strings:
                if "speed" in flag or "step" in flag:
                    assert flag.endswith(("-kmh", "-ms")), (path, flag)


def _eig_json(capsys, *argv):
    assert main(["eig", "--vehicle", "whipple_benchmark", "--json", *argv]) == 0
    captured = capsys.readouterr()
    return json.loads(captured.out), captured.err


def test_kmh_and_ms_speeds_agree(capsys):
    kmh, _ = _eig_json(capsys, "--speeds-kmh", "18", "36")
    ms, _ = _eig_json(capsys, "--speeds-ms", "5", "10")
    assert kmh["speeds_mps"] == pytest.approx(ms["speeds_mps"], rel=1e-12)
    assert np.allclose(kmh["eigenvalues"], ms["eigenvalues"], rtol=1e-9, atol=1e-12)


def test_range_uses_the_stated_default_step(capsys):
    out, _ = _eig_json(capsys, "--range-kmh", "10", "30")
    assert [round(v * 3.6, 9) for v in out["speeds_mps"]] == [10.0, 15.0, 20.0, 25.0, 30.0]


def test_old_forms_work_with_a_deprecation_warning(capsys):
    new, err_new = _eig_json(capsys, "--range-kmh", "10", "20", "--step-kmh", "10")
    old, err_old = _eig_json(capsys, "--range-kmh", "10", "20", "--step", "10")
    assert old == new and "deprecated" not in err_new
    assert "--step is deprecated; use --step-kmh" in err_old
    _, err = _eig_json(capsys, "--speeds", "5")
    assert "--speeds is deprecated" in err


@pytest.mark.parametrize("argv, expected", [
    (["--components", "frame,swingarm"], ["frame", "swingarm"]),     # eig's old style
    (["--components", "frame", "swingarm"], ["frame", "swingarm"]),  # campaign's old style
    (["--component", "frame", "--component", "swingarm"], ["frame", "swingarm"]),
])
def test_component_lists_old_and_new(capsys, argv, expected):
    for verb in (["eig", "--vehicle", "touring", "--speeds-ms", "5"], ["campaign"]):
        args = build_parser().parse_args(verb + argv)
        assert args.component == expected
        err = capsys.readouterr().err
        assert ("deprecated" in err) == ("--components" in argv)
