"""``motoflex view bags/<run> [--web]``: open a run's rerun recording in the viewer.

Native: spawns the rerun viewer on bags/<run>/<run>.rrd (converting the bag first if the .rrd
does not exist yet), its gRPC server bound to 127.0.0.1 (rerun's default is 0.0.0.0:9876) on
a free port (or ``--grpc-port``); without a display (Linux: no DISPLAY, WAYLAND_DISPLAY or
WAYLAND_SOCKET) it refuses in one line and points to ``--web``. ``--web``: serves the web
viewer on 127.0.0.1 only, prints the address and serves until Ctrl-C; the recording reaches
the viewer through its stdin, a pipe left open until the end (rerun 0.41's web viewer given the
file's path spins a core for as long as it serves: 0.8-1.0 CPU-s per second, measured; fed
from an open pipe, none). The viewer runs with
usage analytics off in a configuration folder of its own
(:mod:`motoflex_ros.record.rerun_private`): the user's rerun configuration is neither read
nor written. ``--telemetry`` runs it with the user's configuration as it is.
"""
import contextlib
import os
import signal
import socket
import subprocess
import sys
import threading
import time
from pathlib import Path

from motoflex_ros.errors import MotoflexError

__all__ = ["register", "run", "web_address", "free_port", "native_command", "check_display"]

READY_TIMEOUT_S = 60.0


def register(subparsers):
    parser = subparsers.add_parser(
        "view", help="open a run's rerun recording (native viewer, or --web)",
        description="Open bags/<run>/<run>.rrd in the rerun viewer (converted from the bag "
                    "first if needed). --web serves the web viewer on 127.0.0.1 only.")
    parser.add_argument("run", type=Path, help="run folder bags/<run>")
    parser.add_argument("--web", action="store_true", help="serve the web viewer on 127.0.0.1")
    parser.add_argument("--web-port", type=int, default=0, help="HTTP port (default: free)")
    parser.add_argument("--grpc-port", type=int, default=0, help="gRPC port (default: free)")
    parser.add_argument("--telemetry", action="store_true",
                        help="run the viewer with your own rerun configuration, analytics as "
                             "you set them (default: analytics off, your configuration "
                             "untouched)")
    parser.set_defaults(func=run)


def free_port():
    """A TCP port free on 127.0.0.1 now."""
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        return sock.getsockname()[1]


def web_address(web_port, grpc_port):
    """URL of the web viewer connected to the recording's gRPC proxy (both on 127.0.0.1)."""
    return (f"http://127.0.0.1:{web_port}/?url=rerun%2Bhttp%3A%2F%2F127.0.0.1%3A{grpc_port}"
            "%2Fproxy")


def native_command(rerun, rrd, grpc_port):
    """The native viewer's command line: its gRPC server on 127.0.0.1:``grpc_port`` only."""
    return [rerun, "--bind", "127.0.0.1", "--port", str(grpc_port), str(rrd)]


def check_display(environ=os.environ, platform=sys.platform):
    """MotoflexError when the native viewer has no display to open a window on (Linux)."""
    if platform.startswith("linux") and not any(
            environ.get(k) for k in ("DISPLAY", "WAYLAND_DISPLAY", "WAYLAND_SOCKET")):
        raise MotoflexError("no display for the native viewer (DISPLAY and WAYLAND_DISPLAY "
                            "are not set): use 'motoflex view RUN --web' and open the address "
                            "it prints in a browser")


def _recording(folder):
    from motoflex_ros.cli.recording import write_recording
    from motoflex_ros.record.rerun_bag import rrd_path_of
    rrd = rrd_path_of(folder)
    if not rrd.is_file():
        if not (folder / "metadata.yaml").is_file():
            raise MotoflexError(f"{folder}: no {rrd.name} and no bag to make it from")
        print(f"converting the bag into {rrd} ...", file=sys.stderr)
        write_recording(folder, progress=True)
    return rrd


def _wait_listening(port, child):
    deadline = time.monotonic() + READY_TIMEOUT_S
    while time.monotonic() < deadline:
        if child.poll() is not None:
            raise MotoflexError(f"the rerun viewer exited with code {child.returncode}")
        with socket.socket() as sock:
            if sock.connect_ex(("127.0.0.1", port)) == 0:
                return
        time.sleep(0.1)
    raise MotoflexError(f"the web viewer did not listen on 127.0.0.1:{port} within "
                        f"{READY_TIMEOUT_S:.0f} s")


def _stop(child):
    """End the viewer process: SIGTERM, then SIGKILL if it is still there after 5 s."""
    if child.stdin is not None:
        with contextlib.suppress(OSError):
            child.stdin.close()
    if child.poll() is None:
        child.terminate()
        try:
            child.wait(timeout=5)
        except subprocess.TimeoutExpired:
            child.kill()
            child.wait()


def _feed(rrd, pipe):
    """Copy the recording into the viewer's stdin; leave the pipe open (see _start_web_viewer)."""
    with contextlib.suppress(OSError, ValueError), open(rrd, "rb") as recording:
        while chunk := recording.read(1 << 20):
            pipe.write(chunk)
        pipe.flush()


def _start_web_viewer(command, rrd, web_port, env):
    """Start the web viewer process on ``rrd``; return it once its HTTP port accepts
    connections.

    BROWSER=true keeps the viewer from opening a browser itself: we print the address.
    ``command`` ends with ``-``: the viewer reads the recording from its stdin, a pipe left
    open and silent until :func:`_stop`. Given the file's path instead, rerun 0.41's server
    spins a core for as long as it serves (measured: 0.8-1.0 CPU-s per second, idle, no
    viewer connected; its loop over its log sources, once the file source has been read to
    the end and disconnected, returns at once); an open source keeps that loop blocked (0.0).
    """
    env = dict(env, BROWSER="true")
    child = subprocess.Popen(command, stdin=subprocess.PIPE, stdout=subprocess.DEVNULL,
                             stderr=subprocess.DEVNULL, env=env)
    threading.Thread(target=_feed, args=(rrd, child.stdin), daemon=True).start()
    try:
        _wait_listening(web_port, child)
    except BaseException:
        _stop(child)
        raise
    return child


def _environment(rerun, telemetry):
    """The viewer's environment: the user's own (``telemetry``) or a private one."""
    if telemetry:
        return contextlib.nullcontext(dict(os.environ))
    from motoflex_ros.record.rerun_private import private_rerun_env
    return private_rerun_env(rerun)


def run(args):
    from motoflex_ros.record.rerun_readback import rerun_executable
    from motoflex_ros.report.run_folder import run_folder
    folder = run_folder(args.run)
    if not args.web:
        check_display()
    rrd = _recording(folder)
    rerun = rerun_executable()
    with _environment(rerun, args.telemetry) as env:
        if not args.web:
            return subprocess.call(native_command(rerun, rrd, args.grpc_port or free_port()),
                                   env=env)
        return _serve(rerun, rrd, args, env)


def _serve(rerun, rrd, args, env):
    web_port = args.web_port or free_port()
    grpc_port = args.grpc_port or free_port()
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(0))   # stop the child on SIGTERM too
    child = _start_web_viewer([rerun, "--web-viewer", "--bind", "127.0.0.1", "--web-viewer-port",
                               str(web_port), "--port", str(grpc_port), "-"], rrd, web_port, env)
    try:   # from here on: a SIGTERM right after the address is printed must stop the viewer
        print(f"web viewer of {rrd.name}: {web_address(web_port, grpc_port)}", flush=True)
        print("serving on 127.0.0.1 only; Ctrl-C to stop", file=sys.stderr, flush=True)
        return child.wait()
    finally:
        _stop(child)
