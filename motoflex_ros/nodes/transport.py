"""The ROS transport of every node: one small interface, two implementations, one switch.

What a node needs of ROS beyond rclpy's node, publishers and parameters is three things:

- **take with publisher identity**: each message with the GID of the publisher that sent it
  and its publication sequence number, before the node's callback sees it (the run's trust
  check and per-publisher gap count, :class:`.endpoints.InputGuard`);
- **publish raw CDR**: the bench's per-sample messages are written as CDR bytes
  (:mod:`.cdr`) and published as they are (rclpy's ``Publisher.publish`` takes bytes), patiently
  while a reliable reader is full (:func:`publish_patiently`);
- **spin**: wait for messages and handle every one that is there (``spin_once(timeout_s)`` ->
  the count handled).

:func:`spinner` and :func:`publisher_gid` give these on the selected path:

- ``ctypes`` (default, :mod:`.transport_ctypes`): rcl and rmw through ctypes; the publisher's
  GID per message; checked against named rclpy/rcl/rmw/rcutils releases, refuses others at
  start;
- ``rclpy`` (:mod:`.transport_rclpy`): rclpy's executor and MessageInfo only; runs on any
  release, slower, and without the sender of each message (its docstring says what the trust
  check loses).

The environment variable ``MOTOFLEX_TRANSPORT`` (``ctypes`` or ``rclpy``) selects the path for
a process; the launcher passes its environment to every node of a run, so
``MOTOFLEX_TRANSPORT=rclpy motoflex campaign`` runs the whole graph on the plain path.
"""
import os
import time

from rclpy.impl.implementation_singleton import rclpy_implementation

from motoflex_ros.errors import MotoflexError
from motoflex_ros.nodes import transport_ctypes, transport_rclpy

__all__ = ["TRANSPORT_ENV", "TRANSPORTS", "selected", "selected_name", "spinner",
           "publisher_gid", "publish_patiently"]

TRANSPORT_ENV = "MOTOFLEX_TRANSPORT"
TRANSPORTS = {"ctypes": transport_ctypes, "rclpy": transport_rclpy}


def selected_name(env=None):
    """'ctypes' or 'rclpy': what ``$MOTOFLEX_TRANSPORT`` of ``env`` (default this process's)
    selects (unset or empty: ctypes); MotoflexError for anything else."""
    name = (os.environ if env is None else env).get(TRANSPORT_ENV, "").strip() or "ctypes"
    if name not in TRANSPORTS:
        raise MotoflexError(f"{TRANSPORT_ENV}={name!r}: expected one of "
                            f"{', '.join(TRANSPORTS)}")
    return name


def selected(env=None):
    """The implementation module :func:`selected_name` names; on the ctypes path its versions
    are checked here (a MotoflexError names what is installed and the switch)."""
    name = selected_name(env)
    if name == "ctypes":
        transport_ctypes.check_versions()
    return TRANSPORTS[name]


def spinner(node, check=None):
    """The selected path's spinner of ``node``: ``spin_once(timeout_s)`` handles what arrives
    within ``timeout_s`` [s] and returns the count; ``check(sub, publisher GID or None,
    sequence number)`` (default the node's ``guard.check``) sees every message first."""
    return selected().Spinner(node, check or node.guard.check)


def publisher_gid(publisher, node, known=()):
    """GID (bytes) of ``node``'s new ``publisher`` on the selected path (``known``: the GIDs
    of its publishers so far)."""
    return selected().publisher_gid(publisher, node, known)


def publish_patiently(publisher, msg, timeout_s=30.0):
    """Publish (a message or its CDR bytes), retrying while a reliable keep-all reader is
    full ("cannot publish data": Fast DDS gives up after its blocking time); raises after
    ``timeout_s`` [s] of refusals."""
    deadline = None
    while True:
        try:
            publisher.publish(msg)
            return
        except rclpy_implementation.RCLError as exc:
            if "cannot publish data" not in str(exc):
                raise
            deadline = deadline or time.monotonic() + timeout_s
            if time.monotonic() > deadline:
                raise MotoflexError(f"{publisher.topic_name}: readers refuse data for "
                                    f"{timeout_s:g} s ({exc})") from exc
            time.sleep(0.001)
