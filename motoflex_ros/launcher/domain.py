"""Pick a ROS_DOMAIN_ID in 1-101 that no other run on this machine holds.

Each run holds an exclusive ``fcntl`` lock on ``<tmp>/motoflex_ros_domains/<id>.lock`` for
its lifetime; the lock disappears with the process (even when it is killed), so ids are never
leaked. 1-101 is the range the ROS 2 documentation calls safe on Linux.
"""
import fcntl
import os
import tempfile
from pathlib import Path

from motoflex_ros.errors import MotoflexError

__all__ = ["DomainLock", "DOMAIN_IDS"]

DOMAIN_IDS = range(1, 102)


class DomainLock:
    """Context manager holding a free domain id (``.domain_id``)."""

    def __init__(self, lock_dir=None):
        # one place for every run of this machine, whatever TMPDIR says
        shared = Path("/tmp") if Path("/tmp").is_dir() else Path(tempfile.gettempdir())
        self.lock_dir = Path(lock_dir or shared / "motoflex_ros_domains")
        self.domain_id = None
        self._fd = None

    def acquire(self):
        """Lock the first free id, starting at an offset derived from the pid."""
        self.lock_dir.mkdir(parents=True, exist_ok=True)
        n = len(DOMAIN_IDS)
        start = os.getpid() % n
        for i in range(n):
            candidate = DOMAIN_IDS[(start + i) % n]
            fd = os.open(self.lock_dir / f"{candidate}.lock", os.O_CREAT | os.O_RDWR, 0o666)
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except OSError:
                os.close(fd)
                continue
            self.domain_id, self._fd = candidate, fd
            return candidate
        raise MotoflexError("no free ROS_DOMAIN_ID in 1-101 (101 runs at once?)")

    def release(self):
        """Give the id back."""
        if self._fd is not None:
            os.close(self._fd)
            self._fd = None

    def __enter__(self):
        self.acquire()
        return self

    def __exit__(self, *exc):
        self.release()
