"""SIGINT and SIGTERM during a run, raised where the run can stop cleanly.

A KeyboardInterrupt raised straight from a signal handler surfaces wherever Python happens to
be. Inside rclpy's C++ deserialisation (a message class's ``__init__`` called back through
pybind11) it became "TypeError: Unable to convert function return value to a Python type", a
traceback instead of "interrupted by SIGTERM" (seen once in the fault tests' SIGTERM of a
campaign). So during a run the handlers only note the signal, and the launcher's monitor raises
it from its spin loop (every 0.1 s at most) and once more when the graph has stopped.
"""
import signal
from contextlib import contextmanager

__all__ = ["deferred_interrupts", "raise_if_interrupted", "raise_on_sigterm"]

SIGNALS = (signal.SIGINT, signal.SIGTERM)
_received = []


def raise_on_sigterm(signum, frame):
    """SIGTERM handler outside a graph's run (the run folder's status, launcher/status.py): a
    KeyboardInterrupt('SIGTERM') at once, as SIGINT gives by default."""
    raise KeyboardInterrupt("SIGTERM")


def _note(signum, frame):
    _received.append(signal.Signals(signum).name)


@contextmanager
def deferred_interrupts():
    """Within: SIGINT and SIGTERM are noted, not raised (:func:`raise_if_interrupted` raises
    them); the previous handlers come back on leaving."""
    previous = {s: signal.signal(s, _note) for s in SIGNALS}
    _received.clear()
    try:
        yield
    finally:
        for s, handler in previous.items():
            signal.signal(s, handler)


def raise_if_interrupted():
    """KeyboardInterrupt naming the first signal noted ('SIGINT' or 'SIGTERM'), if any."""
    if _received:
        raise KeyboardInterrupt(_received[0])
