"""DDS stays on loopback and ROS_DOMAIN_ID is honoured (issue 13, points 3 and 7).

Before: during a campaign 56 sockets were bound to 0.0.0.0 and 14 to the Ethernet address (the
discovery range LOCALHOST alone), and an explicit ROS_DOMAIN_ID was ignored. Sockets are read
from /proc: each process's socket inodes (/proc/<pid>/fd) looked up in the machine's UDP and
TCP tables (/proc/net/{udp,udp6,tcp,tcp6}).
"""
import ipaddress
import os
import socket
import subprocess
import sys
import time
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from motoflex_ros.errors import MotoflexError
from motoflex_ros.launcher.domain import (
    DOMAIN_GAIN,
    DOMAIN_IDS,
    PORT_BASE,
    DomainBusy,
    DomainLock,
    domain_in_use,
    requested_domain,
)
from motoflex_ros.nodes.dds import PROFILE_ENV, configure_dds, loopback_profile

RANGE = "ROS_AUTOMATIC_DISCOVERY_RANGE"
NS = "{http://www.eprosima.com/XMLSchemas/fastRTPS_Profiles}"


# --- sockets of a process, from /proc --------------------------------------------------------

def _address(hex_address):
    """'0100007F:1F90' -> ('127.0.0.1', 8080) (IPv4 or IPv6, as /proc/net prints them)."""
    host, port = hex_address.split(":")
    raw = bytes.fromhex(host)
    raw = b"".join(raw[i:i + 4][::-1] for i in range(0, len(raw), 4))  # per 32-bit word
    return str(ipaddress.ip_address(raw)), int(port, 16)


def _socket_table():
    """{inode: (protocol, local address, port)} of every inet socket of this machine."""
    table = {}
    for proto in ("udp", "udp6", "tcp", "tcp6"):
        with open(f"/proc/net/{proto}") as stream:
            next(stream)
            for line in stream:
                fields = line.split()
                table[fields[9]] = (proto, *_address(fields[1]))
    return table


def process_sockets(pid, table=None):
    """[(protocol, local address, port)] of the inet sockets process ``pid`` holds."""
    table = _socket_table() if table is None else table
    found = []
    for fd in Path(f"/proc/{pid}/fd").iterdir():
        try:
            target = os.readlink(fd)
        except OSError:
            continue
        if target.startswith("socket:[") and target[8:-1] in table:
            found.append(table[target[8:-1]])
    return found


def is_loopback(address):
    ip = ipaddress.ip_address(address)
    return ip.is_loopback or bool(getattr(ip, "ipv4_mapped", None)
                                  and ip.ipv4_mapped.is_loopback)


def _children(pid):
    """Pids whose parent is ``pid``."""
    kids = []
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            try:
                stat = (entry / "stat").read_text()
            except OSError:
                continue
            if int(stat.rsplit(")", 1)[1].split()[1]) == pid:
                kids.append(int(entry.name))
    return kids


def _is_node(pid):
    """The process runs a rig node (``python -m motoflex_ros.nodes.X --ros-args ...``). Other
    children (the provenance's short ``git`` calls) and a node caught between fork and exec
    (its environ is still the campaign's) are not nodes yet."""
    argv = Path(f"/proc/{pid}/cmdline").read_bytes().split(b"\0")
    return b"--ros-args" in argv and any(a.startswith(b"motoflex_ros.nodes.") for a in argv)


def _environ(pid):
    raw = Path(f"/proc/{pid}/environ").read_bytes().split(b"\0")
    return dict(item.decode().split("=", 1) for item in raw if b"=" in item)


def test_socket_reader_sees_a_known_socket():
    """The census itself: a socket of this process bound to 127.0.0.1 and one to 0.0.0.0."""
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as lo, \
            socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as anywhere:
        lo.bind(("127.0.0.1", 0))
        anywhere.bind(("0.0.0.0", 0))
        found = set(process_sockets(os.getpid()))
        assert ("udp", "127.0.0.1", lo.getsockname()[1]) in found
        assert ("udp", "0.0.0.0", anywhere.getsockname()[1]) in found
    assert is_loopback("127.0.0.1") and is_loopback("::1") and is_loopback("::ffff:127.0.0.1")
    assert not is_loopback("0.0.0.0") and not is_loopback("192.0.2.2")


# --- DDS configuration -----------------------------------------------------------------------

def test_default_is_the_shipped_loopback_profile():
    env = {"ROS_LOCALHOST_ONLY": "1", RANGE: "SUBNET"}
    said = configure_dds(env)
    assert env == {PROFILE_ENV: str(loopback_profile()), RANGE: "SYSTEM_DEFAULT"}
    assert "loopback" in said and "MOTOFLEX_DDS=network" in said
    again = dict(env)
    configure_dds(again)
    assert again == env   # the launcher's children apply it once more: same result
    root = ET.parse(loopback_profile()).getroot()
    whitelist = [a.text for a in root.iter(f"{NS}interfaceWhiteList") for a in a]
    assert whitelist == ["127.0.0.1"]
    assert {t.text for t in root.iter(f"{NS}type")} == {"UDPv4", "SHM"}
    assert root.find(f".//{NS}useBuiltinTransports").text == "false"
    unicast = root.find(f".//{NS}metatrafficUnicastLocatorList")
    assert [a.text for a in unicast.iter(f"{NS}address")] == ["127.0.0.1"]
    assert root.find(f".//{NS}metatrafficMulticastLocatorList") is None


@pytest.mark.parametrize("name", ["FASTRTPS_DEFAULT_PROFILES_FILE",
                                  "FASTDDS_DEFAULT_PROFILES_FILE"])
def test_own_profile_kept_with_localhost_discovery(name):
    env = {name: "/home/me/dds.xml"}
    assert "/home/me/dds.xml" in configure_dds(env)
    assert env == {name: "/home/me/dds.xml", RANGE: "LOCALHOST"}


def test_network_option_for_a_real_bench():
    env = {"MOTOFLEX_DDS": "network", RANGE: "LOCALHOST"}
    configure_dds(env)
    assert env == {"MOTOFLEX_DDS": "network", RANGE: "SUBNET"}


def test_other_rmw_gets_localhost_discovery():
    env = {"RMW_IMPLEMENTATION": "rmw_cyclonedds_cpp"}
    configure_dds(env)
    assert env == {"RMW_IMPLEMENTATION": "rmw_cyclonedds_cpp", RANGE: "LOCALHOST"}


def test_unknown_dds_mode_refused():
    with pytest.raises(MotoflexError, match="MOTOFLEX_DDS='wifi': expected 'loopback'"):
        configure_dds({"MOTOFLEX_DDS": "wifi"})


# --- ROS_DOMAIN_ID ---------------------------------------------------------------------------

def test_requested_domain_parsed_and_checked():
    assert requested_domain({}) is None and requested_domain({"ROS_DOMAIN_ID": " "}) is None
    assert requested_domain({"ROS_DOMAIN_ID": "0"}) == 0
    assert requested_domain({"ROS_DOMAIN_ID": "232"}) == 232
    for bad in ("abc", "-1", "233", "1.5"):
        with pytest.raises(MotoflexError, match="ROS_DOMAIN_ID=.*expected a whole number"):
            requested_domain({"ROS_DOMAIN_ID": bad})


def test_explicit_domain_honoured_and_busy_one_refused():
    with DomainLock() as free:
        chosen = free.domain_id
    with DomainLock(domain_id=chosen) as mine:
        assert mine.domain_id == chosen and mine.origin == "from ROS_DOMAIN_ID"
        with pytest.raises(DomainBusy, match=f"ROS_DOMAIN_ID {chosen} is in use by another"):
            DomainLock(domain_id=chosen).acquire()
    with DomainLock(domain_id=chosen) as again:   # released with the run
        assert again.domain_id == chosen


def test_free_choice_skips_a_domain_another_ros_graph_uses():
    first = DOMAIN_IDS[os.getpid() % len(DOMAIN_IDS)]   # where this process's search starts
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as participant:
        try:   # a DDS participant's unicast discovery port of that domain
            participant.bind(("127.0.0.1", PORT_BASE + DOMAIN_GAIN * first + 10))
        except OSError:
            pass   # someone else holds it: in use all the same
        assert domain_in_use(first)
        with DomainLock() as lock:
            assert lock.domain_id != first
            assert "free id" in lock.origin


def _cli(*argv, env=None, **kw):
    return subprocess.run([sys.executable, "-m", "motoflex_ros.cli.main", *map(str, argv)],
                          capture_output=True, text=True, timeout=120,
                          env={**os.environ, **(env or {})}, **kw)


def test_campaign_refuses_a_busy_domain_at_once(tmp_path):
    with DomainLock() as other_run:
        start = time.monotonic()
        cli = _cli("campaign", "--component", "swingarm", "--out", tmp_path / "run",
                   "--report", "none", env={"ROS_DOMAIN_ID": str(other_run.domain_id)})
        elapsed = time.monotonic() - start
    assert cli.returncode == 2, cli.stderr
    assert f"ROS_DOMAIN_ID {other_run.domain_id} is in use by another motoflex run" \
        in cli.stderr
    assert "Traceback" not in cli.stderr and elapsed < 10.0
    assert not (tmp_path / "run").exists()


@pytest.mark.parametrize("env, message", [
    ({"ROS_DOMAIN_ID": "lots"}, "ROS_DOMAIN_ID='lots': expected a whole number"),
    ({"MOTOFLEX_DDS": "wifi"}, "MOTOFLEX_DDS='wifi': expected"),
])
def test_campaign_refuses_bad_ros_settings(tmp_path, env, message):
    cli = _cli("campaign", "--component", "swingarm", "--out", tmp_path / "run",
               "--report", "none", env=env)
    assert cli.returncode == 2 and message in cli.stderr and "Traceback" not in cli.stderr
    assert not (tmp_path / "run").exists()
