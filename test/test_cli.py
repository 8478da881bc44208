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


@pytest.mark.parametrize("verb,value", [("identify", "-0.5"), ("identify", "2"),
                                        ("campaign", "-1"), ("campaign", "nan")])
def test_noise_out_of_range_is_refused_before_anything_runs(verb, value, tmp_path):
    """A negative noise once meant "the protocol's" inside the graph: now every verb refuses it,
    naming the option and the range, and writes nothing."""
    out = tmp_path / "out"
    result = run_cli(verb, "--noise", value, "--out", str(out))
    assert result.returncode == 2
    assert "--noise" in result.stderr and "[0, 1] m" in result.stderr
    assert not out.exists()


def test_noise_node_parameter_outside_range_names_it():
    from motoflex_ros.errors import ConfigError
    from motoflex_ros.nodes.bench_graph import campaign_setups
    with pytest.raises(ConfigError, match="ROS parameters: key 'noise'.*got -0.5"):
        campaign_setups({"noise": -0.5, "protocol": "", "components": ["swingarm"]})
