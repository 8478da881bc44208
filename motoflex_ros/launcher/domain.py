"""The ROS_DOMAIN_ID of a run: the one the user set, or a free one in 1-101.

Each run holds an exclusive ``fcntl`` lock on ``<tmp>/motoflex_ros_domains/<id>.lock`` for
its lifetime; the lock disappears with the process (even when it is killed), so ids are never
leaked. An id set in ``ROS_DOMAIN_ID`` is honoured, and refused while another run holds it.
Otherwise the first id that no run holds and whose DDS ports nobody on this machine has bound
(another ROS graph) is taken, from 1-101, the range the ROS 2 documentation calls safe on Linux.

Runs in namespaces of their own (``--namespace /rig_a``: every topic under it) may share a
requested id: each holds the id's lock shared and an exclusive lock on ``<id>@<namespace>``, so
two rigs in one domain never take the same namespace, and a run at the root namespace (whose
topics would meet theirs) still has the id to itself.
"""
import fcntl
import os
import tempfile
from pathlib import Path

from motoflex_ros.errors import MotoflexError

__all__ = ["DomainLock", "DOMAIN_IDS", "DomainBusy", "requested_domain", "domain_in_use",
           "participants_in_domain"]

DOMAIN_IDS = range(1, 102)
MAX_DOMAIN_ID = 232  # the largest id whose DDS ports fit below 65536 (RTPS port mapping)
PORT_BASE, DOMAIN_GAIN = 7400, 250  # RTPS ports of domain d: 7400 + 250 d ... + 249


class DomainBusy(MotoflexError):
    """The requested domain id is held by another run."""


def requested_domain(env):
    """The id ``ROS_DOMAIN_ID`` asks for (an int), or None when it is unset or empty."""
    text = env.get("ROS_DOMAIN_ID", "").strip()
    if not text:
        return None
    if not text.isdigit() or int(text) > MAX_DOMAIN_ID:
        raise MotoflexError(f"ROS_DOMAIN_ID={text!r}: expected a whole number in "
                            f"0-{MAX_DOMAIN_ID} (1-101 are safe on Linux), or unset it to get "
                            "a free one")
    return int(text)


def _bound_udp_ports():
    """Local ports of every UDP socket of this machine (network namespace)."""
    ports = set()
    for name in ("/proc/net/udp", "/proc/net/udp6"):
        try:
            with open(name) as table:
                next(table)
                ports.update(int(line.split()[1].rsplit(":", 1)[1], 16) for line in table)
        except OSError:
            continue
    return ports


def participants_in_domain(domain_id, ports=None):
    """How many DDS participants of this machine are in the domain: ids whose metatraffic
    unicast port (7400 + 250 d + 10 + 2 id) is bound."""
    low = PORT_BASE + DOMAIN_GAIN * domain_id + 10
    ports = _bound_udp_ports() if ports is None else ports
    return sum(1 for port in ports if low <= port < low + DOMAIN_GAIN - 10 and
               (port - low) % 2 == 0)


def domain_in_use(domain_id, ports=None):
    """True if a socket of this machine is bound to one of the domain's RTPS ports."""
    low = PORT_BASE + DOMAIN_GAIN * domain_id
    ports = _bound_udp_ports() if ports is None else ports
    return any(low <= port < low + DOMAIN_GAIN for port in ports)


class DomainLock:
    """Context manager holding a domain id (``.domain_id``): ``domain_id`` if given (refused
    with :class:`DomainBusy` while another run holds it), else a free one."""

    def __init__(self, lock_dir=None, domain_id=None, namespace=None):
        # one place for every run of this machine, whatever TMPDIR says
        shared = Path("/tmp") if Path("/tmp").is_dir() else Path(tempfile.gettempdir())
        self.lock_dir = Path(lock_dir or shared / "motoflex_ros_domains")
        self.requested = domain_id
        self.namespace = (namespace or "/").strip("/")
        self.domain_id = None
        self._fds = []

    def _flock(self, name, shared=False):
        """A file descriptor of lock file ``name`` locked (exclusive or shared), or None."""
        fd = os.open(self.lock_dir / name, os.O_CREAT | os.O_RDWR, 0o666)
        try:
            fcntl.flock(fd, (fcntl.LOCK_SH if shared else fcntl.LOCK_EX) | fcntl.LOCK_NB)
        except OSError:
            os.close(fd)
            return None
        return fd

    def _try_lock(self, candidate, share=False):
        fds = [self._flock(f"{candidate}.lock", shared=share)]
        if share and fds[0] is not None:
            fds.append(self._flock(f"{candidate}@{self.namespace.replace('/', '.')}.lock"))
        if None in fds:
            for fd in fds:
                if fd is not None:
                    os.close(fd)
            return False
        self.domain_id, self._fds = candidate, fds
        return True

    def acquire(self):
        """Lock the requested id, or the first free one from an offset derived from the pid."""
        self.lock_dir.mkdir(parents=True, exist_ok=True)
        if self.requested is not None:
            if not self._try_lock(self.requested, share=bool(self.namespace)):
                where = f" in namespace /{self.namespace}" if self.namespace else ""
                raise DomainBusy(f"ROS_DOMAIN_ID {self.requested} is in use{where} by another "
                                 f"motoflex run on this machine (lock {self.lock_dir}/"
                                 f"{self.requested}.lock); choose another id or namespace, or "
                                 "unset ROS_DOMAIN_ID to get a free one")
            return self.requested
        n = len(DOMAIN_IDS)
        start = os.getpid() % n
        ports = _bound_udp_ports()
        for i in range(n):
            candidate = DOMAIN_IDS[(start + i) % n]
            if not domain_in_use(candidate, ports) and self._try_lock(candidate):
                return candidate
        raise MotoflexError("no free ROS_DOMAIN_ID in 1-101 (101 runs at once?)")

    @property
    def origin(self):
        """How the id was chosen, in words."""
        return ("from ROS_DOMAIN_ID" if self.requested is not None
                else "a free id; set ROS_DOMAIN_ID to choose one")

    def release(self):
        """Give the id back."""
        for fd in self._fds:
            os.close(fd)
        self._fds = []

    def __enter__(self):
        self.acquire()
        return self

    def __exit__(self, *exc):
        self.release()
