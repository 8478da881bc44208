"""Where the rig's DDS traffic may go: loopback only (the default), or a real network.

``MOTOFLEX_DDS`` chooses, for the launcher and for every node's entry point alike:

- ``loopback`` (default): the Fast DDS profile shipped in ``motoflex_ros/config/dds/
  loopback.xml`` (shared memory plus UDP on 127.0.0.1, unicast discovery on 127.0.0.1), with
  ``ROS_AUTOMATIC_DISCOVERY_RANGE=SYSTEM_DEFAULT`` so that the profile decides discovery. The
  discovery range LOCALHOST alone keeps discovery on this host but still opens sockets on every
  interface (0.0.0.0 and the Ethernet address). A profile of your own
  (``FASTRTPS_DEFAULT_PROFILES_FILE``, or ``FASTDDS_DEFAULT_PROFILES_FILE`` of Fast DDS 3) is
  kept, with discovery range LOCALHOST; so is another RMW than Fast DDS.
- ``network``: a real bench on Ethernet. No profile is imposed (yours applies if set) and
  discovery reaches the subnet (``ROS_AUTOMATIC_DISCOVERY_RANGE=SUBNET``; add hosts beyond it
  with ``ROS_STATIC_PEERS``).
"""
import re
from importlib import resources
from pathlib import Path

from motoflex_ros.errors import MotoflexError

__all__ = ["configure_dds", "loopback_profile", "MODE_ENV", "PROFILE_ENV", "peers_range"]

MODE_ENV = "MOTOFLEX_DDS"
MODES = ("loopback", "network")
PROFILE_ENV = "FASTRTPS_DEFAULT_PROFILES_FILE"  # what Fast DDS 2.x (ROS 2 Jazzy) reads
USER_PROFILE_ENVS = (PROFILE_ENV, "FASTDDS_DEFAULT_PROFILES_FILE")
RANGE_ENV = "ROS_AUTOMATIC_DISCOVERY_RANGE"
FAST_DDS_RMWS = ("", "rmw_fastrtps_cpp", "rmw_fastrtps_dynamic_cpp")


def loopback_profile():
    """Path of the shipped loopback profile."""
    return Path(str(resources.files("motoflex_ros") / "config" / "dds" / "loopback.xml"))


def peers_range(env):
    """(maxInitialPeersRange, profile path) of the loopback profile when ``env`` (configured)
    uses it, else (None, None): how many participants of a domain its discovery reaches."""
    ours = str(loopback_profile())
    if env.get(PROFILE_ENV) != ours:
        return None, None
    found = re.search(r"<maxInitialPeersRange>\s*(\d+)", Path(ours).read_text())
    return (int(found.group(1)) if found else 4), ours   # 4: Fast DDS's default


def configure_dds(env):
    """Set the DDS variables of ``env`` (``os.environ`` before ``rclpy.init``, or a child
    process's environment) as ``MOTOFLEX_DDS`` says; returns what was chosen, in words.
    Applying it twice gives the same environment."""
    mode = env.get(MODE_ENV) or "loopback"
    if mode not in MODES:
        raise MotoflexError(f"{MODE_ENV}={mode!r}: expected 'loopback' (the default: DDS on "
                            "127.0.0.1 and shared memory only) or 'network' (a real bench)")
    env.pop("ROS_LOCALHOST_ONLY", None)  # deprecated; it would override the range below
    if mode == "network":
        env[RANGE_ENV] = "SUBNET"
        return f"DDS on the network ({MODE_ENV}=network)"
    ours = str(loopback_profile())
    own = next((env[name] for name in USER_PROFILE_ENVS if env.get(name)), ours)
    rmw = env.get("RMW_IMPLEMENTATION", "")
    if own != ours or rmw not in FAST_DDS_RMWS:
        env[RANGE_ENV] = "LOCALHOST"
        return (f"DDS discovery on localhost with {rmw} (no loopback profile)" if own == ours
                else f"DDS discovery on localhost, your DDS profile {own}")
    if not Path(ours).is_file():   # never fall back to every interface silently
        raise MotoflexError(f"the loopback DDS profile {ours} is missing from this install "
                            f"(package data); reinstall motoflex_ros, or set {MODE_ENV}=network")
    env[PROFILE_ENV] = ours
    env[RANGE_ENV] = "SYSTEM_DEFAULT"   # the profile's discovery: 127.0.0.1 only
    return f"DDS on loopback only ({MODE_ENV}=network for a real network)"
