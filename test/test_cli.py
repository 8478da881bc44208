"""Every verb of the ``motoflex`` command answers --help; user errors exit non-zero."""
import subprocess
import sys

import pytest

from motoflex_ros.cli.main import build_parser


def verbs():
    parser = build_parser()
    action = next(a for a in parser._actions if a.dest == "verb")
    return sorted(action.choices)


def run_cli(*args):
    return subprocess.run([sys.executable, "-m", "motoflex_ros.cli.main", *args],
                          capture_output=True, text=True)


def test_main_help_lists_verbs():
    result = run_cli("--help")
    assert result.returncode == 0
    for verb in verbs():
        assert verb in result.stdout


@pytest.mark.parametrize("verb", verbs())
def test_every_verb_has_help(verb):
    result = run_cli(verb, "--help")
    assert result.returncode == 0, result.stderr
    assert "usage: motoflex" in result.stdout


def test_unknown_verb_exits_non_zero():
    assert run_cli("no-such-verb").returncode != 0
