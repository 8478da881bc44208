"""Outputs (issue 23, points 1, 13 and 15): only a regular file or a new path is ever written.

A device, FIFO, socket or directory given as an output is refused by name, with --force too,
and is still what it was afterwards (run as root, a rename over /dev/null replaced it for the
whole machine). A folder on the way that is a file is named as such. A full disk names the
file being written, leaves no temporary file, and a run that was started still gets its
'failed' status. The real full disk is a small tmpfs (mounting needs root: skipped without).
"""
import errno
import json
import os
import socket
import stat
import subprocess
import sys
import tempfile
from pathlib import Path

import pytest
from hostile import refused, write_rig

from motoflex_ros import files
from motoflex_ros.files import OutputError, atomic_write_text
from motoflex_ros.launcher.status import read_status, run_status
from motoflex_ros.record.mcap_bag import BagWriter


@pytest.fixture(scope="module")
def measured(tmp_path_factory):
    """``identify --measured`` of a measured CSV and its bench file (writes --out in ~1 s)."""
    csv_path, bench = write_rig(tmp_path_factory.mktemp("measured"))
    return ["identify", "--measured", csv_path, "--bench", bench]


@pytest.fixture()
def short_dir():
    """A folder with a short path (a UNIX socket's path is at most 107 bytes)."""
    folder = Path(tempfile.mkdtemp(prefix="mf_", dir="/tmp"))
    yield folder
    for p in folder.iterdir():
        p.unlink()
    folder.rmdir()


def _mode(path):
    return os.lstat(path).st_mode


# --- point 1: a device, FIFO, socket or directory is never replaced -------------------------

def test_dev_null_is_refused_with_force(measured, capsys):
    """`identify --out /dev/null --force` as root replaced /dev/null with a regular file."""
    before = os.stat("/dev/null")
    refused([*measured, "--out", "/dev/null", "--force"], capsys, "--out", "/dev/null",
            "character device", "even with --force")
    after = os.stat("/dev/null")
    assert stat.S_ISCHR(after.st_mode) and after.st_rdev == before.st_rdev


@pytest.mark.parametrize("kind", ["fifo", "socket", "directory", "link to /dev/null"])
def test_special_outputs_are_refused_and_kept(measured, capsys, short_dir, kind):
    target = short_dir / "out.json"
    if kind == "fifo":
        os.mkfifo(target)
        words = ["FIFO"]
    elif kind == "socket":
        server = socket.socket(socket.AF_UNIX)
        server.bind(str(target))
        server.close()
        words = ["socket"]
    elif kind == "directory":
        target.mkdir()
        words = ["directory"]
    else:
        target.symlink_to("/dev/null")
        words = ["character device"]
    before = _mode(target)
    refused([*measured, "--out", target, "--force"], capsys, target, *words)
    assert _mode(target) == before
    assert stat.S_ISCHR(os.stat("/dev/null").st_mode)
    if kind == "directory":
        target.rmdir()


@pytest.mark.parametrize("kind", ["fifo", "/dev/null", "directory", "socket"])
def test_the_atomic_writer_refuses_every_special_target(short_dir, kind):
    """The class of fix: the one writer every output goes through (results, bags' metadata,
    status, reports) checks the target, so no verb can replace a special file."""
    target = {"/dev/null": Path("/dev/null")}.get(kind, short_dir / "x")
    if kind == "fifo":
        os.mkfifo(target)
    elif kind == "directory":
        target.mkdir()
    elif kind == "socket":
        server = socket.socket(socket.AF_UNIX)
        server.bind(str(target))
        server.close()
    before = _mode(target)
    with pytest.raises(OutputError, match="not a regular file"):
        atomic_write_text(target, "x")
    assert _mode(target) == before
    assert [p.name for p in short_dir.iterdir()] == ([] if kind == "/dev/null" else ["x"])
    if kind == "directory":
        target.rmdir()


def test_a_link_to_a_regular_file_is_followed(tmp_path):
    """A symbolic link to a regular file: the file is replaced, the link stays a link."""
    real = tmp_path / "real.json"
    real.write_text("old")
    link = tmp_path / "link.json"
    link.symlink_to(real)
    atomic_write_text(link, "new")
    assert link.is_symlink() and real.read_text() == "new"


# --- point 15: a folder on the way that is a file -------------------------------------------

def test_a_folder_that_is_a_file_is_named(measured, capsys, tmp_path):
    """`--out afile/o.json` said "File exists: 'afile'"."""
    afile = tmp_path / "afile"
    afile.write_text("mine")
    err = refused([*measured, "--out", afile / "o.json"], capsys, "afile",
                  "is not a directory")
    assert "File exists" not in err
    assert afile.read_text() == "mine"
    with pytest.raises(OutputError, match="is not a directory"):
        atomic_write_text(afile / "deeper" / "o.json", "x")


# --- point 13: a full disk ------------------------------------------------------------------

def _full_disk(monkeypatch, times=1):
    """Make the atomic writer's next ``times`` writes fail as on a full disk, after half the
    data (at the lowest level: the loop of os.write calls)."""
    real, left = files._write_all, [times]

    def write_half(fd, data):
        if left[0] <= 0:
            return real(fd, data)
        left[0] -= 1
        os.write(fd, bytes(data[:len(data) // 2]))
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
    monkeypatch.setattr(files, "_write_all", write_half)


def test_disk_full_names_the_file_and_leaves_nothing(measured, capsys, tmp_path, monkeypatch):
    _full_disk(monkeypatch)
    out = tmp_path / "result.json"
    refused([*measured, "--out", out], capsys, out, "No space left on device", "disk is full")
    assert list(tmp_path.iterdir()) == []


def test_disk_full_run_is_marked_failed(tmp_path, monkeypatch):
    """A run whose result write fails for a full disk ends 'failed', naming the file."""
    folder = tmp_path / "run"
    with pytest.raises(OutputError):
        with run_status(folder, ["identification.json"]):
            folder.mkdir()
            _full_disk(monkeypatch)
            atomic_write_text(folder / "identification.json", "{}")
    status = read_status(folder)
    assert status["status"] == "failed"
    assert "identification.json" in status["reason"] and "No space" in status["reason"]


def _mount(folder, options):
    if os.geteuid() != 0:
        pytest.skip("mounting a small tmpfs needs root")
    folder.mkdir()
    run = subprocess.run(["mount", "-t", "tmpfs", "-o", options, "tmpfs", str(folder)],
                         capture_output=True, text=True)
    if run.returncode:
        pytest.skip(f"mounting a tmpfs is not permitted here ({run.stderr.strip()})")


def _unmount(folder):
    """Unmount ``folder``; a file left open there is a failure of the test, but the mount is
    detached anyway (lazily) so that nothing stays mounted."""
    if subprocess.run(["umount", str(folder)], capture_output=True).returncode:
        subprocess.run(["umount", "-l", str(folder)], check=True)
        pytest.fail(f"{folder}: a file was left open on the small disk")


@pytest.fixture()
def small_disk(tmp_path):
    """A 256 kB tmpfs (a disk that fills up)."""
    disk = tmp_path / "disk"
    _mount(disk, "size=256k")
    yield disk
    _unmount(disk)


def _fill(folder):
    """Fill the disk holding ``folder`` with a file (nothing left to write)."""
    with open(folder / "filler", "wb", buffering=0) as stream:
        with pytest.raises(OSError) as info:
            while True:
                stream.write(bytes(4096))
    assert info.value.errno == errno.ENOSPC


def test_real_full_disk_still_gets_the_failed_status(small_disk):
    """On a real full disk (tmpfs) the run's status is written: room for it was kept aside
    while the run went (without it the status write fails like every other one)."""
    folder = small_disk / "run"
    with pytest.raises(OutputError) as info:
        with run_status(folder, ["identification.json"]):
            folder.mkdir()
            _fill(folder)
            atomic_write_text(folder / "identification.json", "{}" * 1000)
    assert "identification.json" in str(info.value) and "disk is full" in str(info.value)
    status = read_status(folder)
    assert status["status"] == "failed" and "identification.json" in status["reason"]
    assert not [p for p in small_disk.iterdir() if p.name.endswith("status-reserve")]


def test_real_full_disk_names_the_bag_being_recorded(small_disk):
    """The recorder's MCAP file, written as messages come: the error names it."""
    with pytest.raises(OutputError) as info:
        with BagWriter(small_disk / "bag", chunk_size=4096, compression="none") as bag:
            bag.add_topic("/x", "std_msgs/msg/String")
            for i in range(10_000):
                bag.write("/x", i, bytes(8) + os.urandom(256))
    assert "bag_0.mcap" in str(info.value) and "disk is full" in str(info.value)


# --- own cases ------------------------------------------------------------------------------

def test_read_only_folder(measured, capsys, tmp_path):
    """--out into a read-only file system (root ignores file modes, not a read-only mount)."""
    disk = tmp_path / "ro"
    _mount(disk, "ro,size=64k")
    try:
        refused([*measured, "--out", disk / "o.json"], capsys, disk / "o.json",
                "Read-only file system")
    finally:
        _unmount(disk)


def test_symlink_loop_as_output(measured, capsys, tmp_path):
    loop = tmp_path / "loop.json"
    loop.symlink_to(tmp_path / "loop.json")
    refused([*measured, "--out", loop, "--force"], capsys, loop, "symbolic links")
    assert loop.is_symlink()


def test_name_too_long_as_output(measured, capsys, tmp_path):
    out = tmp_path / ("x" * 300 + ".json")
    refused([*measured, "--out", out], capsys, "x" * 300, "File name too long")


def test_export_refuses_a_fifo_in_place_of_a_matrix(capsys, tmp_path):
    """`components --export DIR` writes three files; one of them a FIFO: refused, and the
    FIFO is still one (no process blocked on it)."""
    os.mkfifo(tmp_path / "tube_K.mtx")
    run = subprocess.run([sys.executable, "-m", "motoflex_ros.cli.main", "components",
                          "--component", "tube", "--export", str(tmp_path)],
                         capture_output=True, text=True, timeout=60)
    assert run.returncode == 2 and "Traceback" not in run.stderr, run.stderr
    assert "tube_K.mtx" in run.stderr and "FIFO" in run.stderr
    assert stat.S_ISFIFO(_mode(tmp_path / "tube_K.mtx"))


def test_campaign_on_a_full_disk_fails_naming_the_bag(tmp_path):
    """The whole graph on a 400 kB disk (a process: ROS nodes, in a free domain): the
    recorder fills it; the run ends 'failed' in its status.json, and the one-line error (in
    the status and on stderr) names the MCAP file being written, without a traceback."""
    disk = tmp_path / "disk"
    _mount(disk, "size=400k")
    try:
        env = {k: v for k, v in os.environ.items() if k != "ROS_DOMAIN_ID"}   # a free one
        env["ROS_LOG_DIR"] = str(tmp_path / "ros_log")
        run = subprocess.run([sys.executable, "-m", "motoflex_ros.cli.main", "campaign",
                              "--component", "tube", "--out", str(disk / "run"),
                              "--report", "none"], env=env, capture_output=True, text=True,
                             timeout=600)
        error = run.stderr.strip().splitlines()[-1]
        assert run.returncode == 2 and "Traceback" not in run.stderr, run.stderr[-3000:]
        assert error.startswith("motoflex campaign: error:"), error
        assert str(disk / "run" / "run_0.mcap") in error and "disk is full" in error
        status = json.loads((disk / "run" / "status.json").read_text())
        assert status["status"] == "failed" and "run_0.mcap" in status["reason"]
        assert not (disk / "run" / "identification.json").exists()
    finally:
        _unmount(disk)
