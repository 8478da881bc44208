"""Writing files so that nothing half-written is ever left, and nothing that is not a file is
ever replaced: a temporary file in the target's folder, then an atomic rename. Used by every
writer of the package (results, plots, bags, status).

The target must be a regular file (replaced) or a new path. A device (/dev/null), a FIFO, a
socket or a directory is refused before anything is written, whatever ``--force`` says: a
rename over it would put a regular file in its place for the whole machine. A symbolic link is
followed (its target is written, the link stays). Every failure, a full disk too, is an
:class:`OutputError` naming the file being written.
"""
import errno
import io
import json
import os
import stat
import tempfile
from pathlib import Path

from motoflex_ros.errors import MotoflexError

__all__ = ["OutputError", "check_output_path", "atomic_write_bytes", "atomic_write_text",
           "atomic_save_figure", "file_kind", "open_output", "read_json", "missing_file_text"]

_KINDS = ((stat.S_ISDIR, "a directory"), (stat.S_ISCHR, "a character device"),
          (stat.S_ISBLK, "a block device"), (stat.S_ISFIFO, "a FIFO (named pipe)"),
          (stat.S_ISSOCK, "a socket"))


class OutputError(MotoflexError, OSError):
    """An output file that cannot or must not be written; the message names it."""

    def __init__(self, path, problem):
        self.path = str(path)
        super().__init__(f"{path}: {problem}")


def file_kind(mode):
    """'a directory', 'a FIFO (named pipe)', ... of an ``st_mode``; None for a regular file."""
    for test, name in _KINDS:
        if test(mode):
            return name
    return None if stat.S_ISREG(mode) else "not a regular file"


def missing_file_text(path):
    """Why an input ``path`` that is not a regular file cannot be read, in words: 'file not
    found', 'is a directory, not a regular file', 'is a FIFO (named pipe), not a regular
    file' (never opened: reading a FIFO or a device would block or never end)."""
    try:
        kind = file_kind(os.stat(path).st_mode)
    except FileNotFoundError:
        return "file not found"
    except OSError as exc:
        return f"cannot be read ({_os_problem(exc)})"
    return f"is {kind}, not a regular file" if kind else "a regular file"


def _os_problem(exc):
    return exc.strerror or str(exc)


def _target(path):
    """``path`` with a symbolic link followed; OutputError if it exists and is not a regular
    file, or if a folder on the way is a file."""
    try:
        mode = os.stat(path).st_mode
    except FileNotFoundError:
        mode = None
    except NotADirectoryError:
        mode = None   # reported below, naming the part of the path that is a file
    except OSError as exc:   # a symlink loop (ELOOP), permission denied, a name too long
        raise OutputError(path, f"cannot be written ({_os_problem(exc)})") from None
    if mode is not None:
        kind = file_kind(mode)
        if kind:
            raise OutputError(path, f"is {kind}, not a regular file: refused (only a regular "
                                    f"file is replaced, even with --force); give a file name")
        return Path(os.path.realpath(path))
    if os.path.islink(path):   # a dangling link: write where it points
        return Path(os.path.realpath(path))
    for parent in reversed(path.parents):
        if parent.exists() and not parent.is_dir():
            raise OutputError(path, f"its folder {parent} is not a directory (it is "
                                    f"{file_kind(parent.stat().st_mode) or 'a file'})")
    return path


def check_output_path(path):
    """``path`` (a Path, a symbolic link followed) if it may be written: a regular file or a
    new path whose folders are directories (or can be made); else OutputError naming it."""
    return _target(Path(path))


def _umask_mode():
    mask = os.umask(0)
    os.umask(mask)
    return 0o666 & ~mask


def _write_all(fd, data):
    view = memoryview(data)
    while view:
        view = view[os.write(fd, view):]


def _write_failed(path, exc):
    full = " (the disk is full)" if exc.errno in (errno.ENOSPC, errno.EDQUOT) else ""
    return OutputError(path, f"writing failed: {_os_problem(exc)}{full}")


class _NamedFile(io.FileIO):
    """A raw binary file whose write errors (a full disk) name it."""

    def write(self, data):
        try:
            return super().write(data)
        except OSError as exc:
            raise _write_failed(self.name, exc) from None


def open_output(path):
    """A new buffered binary file at ``path`` for a stream written as it comes (a bag being
    recorded): refused like :func:`atomic_write_bytes` when ``path`` is not a regular file or a
    new path; a write that fails (a full disk) is an OutputError naming it."""
    target = check_output_path(path)
    try:
        return io.BufferedWriter(_NamedFile(str(target), "w"))
    except OSError as exc:
        raise OutputError(path, f"cannot be written ({_os_problem(exc)})") from None


def atomic_write_bytes(path, data):
    """Write ``data`` to ``path`` via a temporary file and a rename; returns the path.

    OutputError (nothing written, no temporary file left) when ``path`` is not a regular file
    or a new path, or when its folder cannot be made or written, or the disk is full."""
    path = Path(path)
    target = check_output_path(path)
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(dir=target.parent, prefix=f".{target.name}.", suffix=".tmp")
    except OSError as exc:
        raise OutputError(path, f"cannot be written: its folder {target.parent} "
                                f"({_os_problem(exc)})") from None
    try:
        try:
            _write_all(fd, data)
        finally:
            os.close(fd)
        os.chmod(tmp, _umask_mode())   # mkstemp makes 0600; give the usual permissions
        os.replace(tmp, target)
    except OSError as exc:
        Path(tmp).unlink(missing_ok=True)
        raise _write_failed(path, exc) from None
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return path


def read_json(path):
    """The data of the JSON file ``path``; OSError if it cannot be read, ValueError (a
    one-line reason) if it is not UTF-8 JSON or is nested too deeply for Python (a file of
    100,000 nested lists)."""
    text = Path(path).read_text(encoding="utf-8")
    try:
        return json.loads(text)
    except RecursionError:
        raise ValueError("nested too deeply to be read") from None


def atomic_write_text(path, text):
    """Write ``text`` (UTF-8) atomically; returns the path."""
    return atomic_write_bytes(path, text.encode("utf-8"))


def atomic_save_figure(fig, path, dpi=120):
    """Save a matplotlib figure as PNG atomically (rendered in memory first); returns the path."""
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", dpi=dpi)
    return atomic_write_bytes(path, buffer.getvalue())
