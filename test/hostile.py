"""Helpers of the hostile input and output tests (issue 23): run ``motoflex`` in this process
(or, where a hang is possible, in a child with a timeout) and check a refusal: a non-zero exit,
one line naming what and where, no traceback, within CPU_GUARD_S."""
import contextlib
import io
import os
import subprocess
import sys
import time

CPU_GUARD_S = 10.0   # [s] of the command's CPU time
WALL_GUARD_S = 10.0  # [s] of a child's wall time (what could hang: a FIFO, a device)


def write_rig(folder):
    """A measured cantilever record in ``folder``: (rig.csv, bench.yaml); ``identify
    --measured`` takes about a second on it."""
    from measured_cases import bench_yaml, cantilever_record

    from motoflex_ros.formats.measured_csv import write_csv
    t, wrench, points, _, q0 = cantilever_record(noise_m=5e-6)
    write_csv(folder / "rig.csv", t, wrench, points)
    (folder / "bench.yaml").write_text(bench_yaml("rig", q0, "from_data"))
    return folder / "rig.csv", folder / "bench.yaml"


def cli(argv, capsys):
    """(exit code, stderr, CPU time [s]) of ``motoflex argv`` run in this process."""
    from motoflex_ros.cli.main import main
    start = time.process_time()
    code = main([str(a) for a in argv])
    err = capsys.readouterr().err.strip()
    return code, err, time.process_time() - start


def run_motoflex(argv, cwd=None):
    """``motoflex argv`` run in this process (in ``cwd``), returned as ``subprocess.run(...,
    capture_output=True, text=True)`` returns a child's: the CLI's own start-up (an interpreter,
    numpy, scipy: 1-3 CPU-s a call) is what a child adds, not what the tests check. Not for a
    verb that starts ROS nodes or could block (refused_in_child)."""
    from motoflex_ros.cli.main import main
    out, err, here = io.StringIO(), io.StringIO(), os.getcwd()
    try:
        os.chdir(cwd or here)
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            try:
                code = main([str(a) for a in argv])
            except SystemExit as exc:       # argparse's refusals
                code = exc.code if isinstance(exc.code, int) else int(exc.code is not None)
    finally:
        os.chdir(here)
    return subprocess.CompletedProcess(argv, code, out.getvalue(), err.getvalue())


def check_refusal(code, err, cpu, words):
    """Assert a refusal: non-zero exit, one line holding every word, no traceback, CPU bound."""
    assert code != 0, err
    assert len(err.splitlines()) == 1 and "Traceback" not in err, err
    for word in words:
        assert str(word) in err, (word, err)
    assert cpu < CPU_GUARD_S
    return err


def refused(argv, capsys, *words):
    """Run ``argv`` in this process and check the refusal; returns the message."""
    return check_refusal(*cli(argv, capsys), words)


def refused_in_child(argv, *words, module="motoflex_ros.cli.main", env=None):
    """Run ``argv`` of ``module`` (the motoflex command, or a node) in a child process (a
    command that could block) and check the refusal within WALL_GUARD_S; returns the
    message."""
    start = time.monotonic()
    run = subprocess.run([sys.executable, "-m", module, *map(str, argv)], env=env,
                         capture_output=True, text=True, timeout=WALL_GUARD_S + 50)
    wall = time.monotonic() - start
    assert wall < WALL_GUARD_S + 50
    return check_refusal(run.returncode, run.stderr.strip(), 0.0, words)
