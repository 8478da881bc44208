"""DDS stays on loopback and ROS_DOMAIN_ID is honoured (issue 13, points 3 and 7).

Before: during a campaign 56 sockets were bound to 0.0.0.0 and 14 to the Ethernet address (the
discovery range LOCALHOST alone), and an explicit ROS_DOMAIN_ID was ignored. Sockets are read
from /proc: each process's socket inodes (/proc/<pid>/fd) looked up in the machine's UDP and
TCP tables (/proc/net/{udp,udp6,tcp,tcp6}).
"""
import ipaddress
import json
import os
import signal
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


# --- with ROS ---------------------------------------------------------------------------------

def _node_env(domain_id, tmp_path, **extra):
    env = {k: v for k, v in os.environ.items()
           if k not in ("FASTRTPS_DEFAULT_PROFILES_FILE", "MOTOFLEX_DDS")}
    return {**env, "ROS_DOMAIN_ID": str(domain_id), "ROS_LOG_DIR": str(tmp_path / "log"),
            RANGE: "SUBNET", **extra}


def _node_sockets(tmp_path):
    """Start sim_clock on its own; its sockets once discovery runs, its exit code, stderr."""
    with DomainLock() as lock:
        proc = subprocess.Popen([sys.executable, "-m", "motoflex_ros.nodes.sim_clock",
                                 "--ros-args", "-p", "duration:=100.0",
                                 "-p", "stall_timeout:=3600.0"],
                                env=_node_env(lock.domain_id, tmp_path),
                                text=True, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
        try:
            # a hang guard, not a timing check: under a loaded machine the node's imports
            # alone took over 30 s once (full suite beside other jobs, load average 9)
            deadline, sockets = time.monotonic() + 180.0, []
            while len(sockets) < 3 and time.monotonic() < deadline and proc.poll() is None:
                time.sleep(0.2)
                sockets = process_sockets(proc.pid)
            time.sleep(1.0)   # discovery has started by now
            sockets = process_sockets(proc.pid) if proc.poll() is None else sockets
            early = proc.poll()
        finally:
            proc.send_signal(signal.SIGINT)
            _, err = proc.communicate(timeout=30)
    return sockets, early, err


@pytest.mark.ros
def test_node_entry_point_binds_loopback_by_itself(tmp_path):
    """A node started on its own (``ros2 run``, no launcher) sets the profile too. Every
    socket it binds is on loopback. The node is still running when looked at: a sim_clock
    alone waits for a subscriber of /clock (it once counted its own time source's and ran its
    whole run to itself, ending at start-up in about one start in ten)."""
    pytest.importorskip("rclpy")
    sockets, early, err = _node_sockets(tmp_path)
    assert early is None, (early, err)
    assert all(is_loopback(address) for _, address, _ in sockets), sockets
    assert len(sockets) >= 3, (sockets, err)


@pytest.mark.ros
def test_node_refuses_unknown_dds_mode(tmp_path):
    pytest.importorskip("rclpy")
    with DomainLock() as lock:
        run = subprocess.run([sys.executable, "-m", "motoflex_ros.nodes.sim_clock"],
                             env=_node_env(lock.domain_id, tmp_path, MOTOFLEX_DDS="wifi"),
                             capture_output=True, text=True, timeout=60)
    assert run.returncode == 2
    assert "sim_clock: error: MOTOFLEX_DDS='wifi'" in run.stderr and "Traceback" not in run.stderr


@pytest.mark.ros
@pytest.mark.slow
def test_campaign_sockets_on_loopback_and_explicit_domain_honoured(tmp_path):
    """A whole campaign (swingarm, --json) on an explicit ROS_DOMAIN_ID: every socket of every
    process of the run is bound to loopback, every node runs on that domain, the id is
    printed on stderr at the start and stdout stays clean JSON."""
    pytest.importorskip("rclpy")
    with DomainLock() as free:
        domain = free.domain_id
    bag = tmp_path / "run"
    proc = subprocess.Popen([sys.executable, "-m", "motoflex_ros.cli.main", "campaign",
                             "--component", "swingarm", "--out", str(bag), "--report", "none",
                             "--json"], env=_node_env(domain, tmp_path, TMPDIR=str(tmp_path)),
                            text=True, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    seen, node_envs = {}, {}
    try:
        deadline = time.monotonic() + 300
        while proc.poll() is None and time.monotonic() < deadline:
            table = _socket_table()
            for pid in [proc.pid, *_children(proc.pid)]:
                try:
                    seen.setdefault(pid, set()).update(process_sockets(pid, table))
                    if pid != proc.pid and _is_node(pid):
                        node_envs[pid] = _environ(pid)   # a node's start env
                except OSError:
                    continue   # ended meanwhile
            time.sleep(0.5)
        out, err = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.communicate()
    assert proc.returncode == 0, err
    printed = json.loads(out)   # stdout: the results as JSON, nothing else
    assert "swingarm" in printed and printed["bag"] == str(bag)
    assert printed["stability"] is None       # no motorcycle without all three components
    assert f"motoflex: ROS_DOMAIN_ID {domain} (from ROS_DOMAIN_ID); DDS on loopback" in err
    assert len(node_envs) >= 5, node_envs
    assert {env.get("ROS_DOMAIN_ID") for env in node_envs.values()} == {str(domain)}
    assert {env.get(PROFILE_ENV) for env in node_envs.values()} == {str(loopback_profile())}
    with_sockets = {pid: s for pid, s in seen.items() if s}
    assert len(with_sockets) >= 6, seen   # the campaign's own node + 5 node processes
    assert sum(map(len, with_sockets.values())) >= 18, seen
    outside = {pid: [s for s in socks if not is_loopback(s[1])]
               for pid, socks in with_sockets.items()}
    assert not any(outside.values()), outside
    status = json.loads((bag / "status.json").read_text())
    assert status["status"] == "complete"
