"""Every verb of the ``motoflex`` command answers --help; user errors exit non-zero."""
import pytest
from hostile import run_motoflex

from motoflex_ros.cli.main import build_parser


def verbs():
    parser = build_parser()
    action = next(a for a in parser._actions if a.dest == "verb")
    return sorted(action.choices)


def run_cli(*args):
    """``motoflex args`` in this process (hostile.run_motoflex: the parser and the verbs' checks
    of their options are what these tests hold, not the interpreter's start-up)."""
    return run_motoflex(args)


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


@pytest.mark.parametrize("verb,value", [("identify", "-0.5"), ("identify", "1"),
                                        ("campaign", "-1"), ("campaign", "nan")])
def test_noise_out_of_range_is_refused_before_anything_runs(verb, value, tmp_path):
    """A negative noise once meant "the protocol's" inside the graph, and a noise of 1 m gave a
    negative k: every verb refuses a noise outside [0, 1 mm] (the bench's largest deformation
    is 1.3 mm), naming the option and the range, and writes nothing."""
    out = tmp_path / "out"
    result = run_cli(verb, "--noise", value, "--out", str(out))
    assert result.returncode == 2
    assert "--noise" in result.stderr and "[0, 0.001] m" in result.stderr
    assert "Traceback" not in result.stderr
    assert not out.exists()


def refused_option(capsys, *argv):
    """The error text of a motoflex command line (run in this process) that argparse refuses."""
    from motoflex_ros.cli.main import main
    with pytest.raises(SystemExit) as info:
        main(list(argv))
    assert info.value.code == 2
    return capsys.readouterr().err


@pytest.mark.parametrize("verb,value", [("identify", "0.002"), ("campaign", "0.5")])
def test_noise_above_a_millimetre_is_refused(verb, value, capsys, tmp_path):
    err = refused_option(capsys, verb, "--noise", value, "--out", str(tmp_path / "out"))
    assert "--noise" in err and "[0, 0.001] m" in err
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("verb,value", [("identify", "-1"), ("identify", "1.5"),
                                        ("campaign", "-1"), ("campaign", "2147483648")])
def test_seed_out_of_range_is_refused_before_anything_runs(verb, value, capsys, tmp_path):
    """A negative seed ran into a traceback deep in the run (numpy); the option refuses it."""
    err = refused_option(capsys, verb, f"--seed={value}", "--out", str(tmp_path / "out"))
    assert "--seed" in err and "whole number in [0, 2147483647]" in err
    assert not (tmp_path / "out").exists()


def test_noise_node_parameter_range_is_the_offline_bound():
    from motoflex_ros.bench.sensor import MAX_NOISE_M
    from motoflex_ros.nodes.bench_graph import BENCH_PARAMS
    from motoflex_ros.nodes.params import ParameterError
    noise = next(p for p in BENCH_PARAMS if p.name == "noise")
    assert noise.check("bench", MAX_NOISE_M) == MAX_NOISE_M
    with pytest.raises(ParameterError, match="noise"):
        noise.check("bench", 0.5)


def test_noise_node_parameter_outside_range_names_it():
    from motoflex_ros.errors import ConfigError
    from motoflex_ros.nodes.bench_graph import campaign_setups
    with pytest.raises(ConfigError, match="ROS parameters: key 'noise'.*got -0.5"):
        campaign_setups({"noise": -0.5, "protocol": "", "components": ["swingarm"]})
