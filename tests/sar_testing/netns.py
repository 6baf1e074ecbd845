"""A small network of Linux network namespaces for tests: hosts joined by one bridge.

Each host is a network namespace of its own with a loopback and one veth into a bridge,
which lives in a further namespace made for it. Processes started in a host see only that
host's interfaces, so DDS treats the hosts as separate machines; nothing is attached to
the machine's own namespace, so no packet can leave the lab. Discovery between hosts goes
over the bridge to static peers (``ROS_STATIC_PEERS``) while automatic discovery stays
``LOCALHOST``, as every local run here sets it (rmw_fastrtps still adds the static peers;
with ``OFF`` it discovers nothing, measured with Jazzy's wheels)::

    with NetworkLab(["world", "robot1"]) as lab:
        NodeProcess([...], "sim", prefix=lab.enter("world"), env=lab.ros_env("world"))

Needs root and iproute2's ``ip``; :func:`netns_unavailable` says why not otherwise.
"""

from __future__ import annotations

import itertools
import os
import shutil
import subprocess
from collections.abc import Sequence
from pathlib import Path
from types import TracebackType

_labs = itertools.count(1)

#: The lab's subnet: hosts get .1, .2, ... in the order given.
SUBNET_PREFIX = "10.231.0."


def netns_unavailable() -> str | None:
    """Why a network-namespace lab cannot be made here, or None when it can."""
    if os.geteuid() != 0:
        return "network namespaces need root"
    if shutil.which("ip") is None:
        return "network namespaces need iproute2's ip command"
    probe = f"sarprobe{os.getpid()}"
    made = subprocess.run(["ip", "netns", "add", probe], check=False,
                          capture_output=True, text=True)
    if made.returncode != 0:
        return f"cannot create a network namespace: {made.stderr.strip()}"
    subprocess.run(["ip", "netns", "delete", probe], check=False, capture_output=True)
    return None


def _ip(*args: str) -> None:
    result = subprocess.run(["ip", *args], check=False, capture_output=True, text=True)
    if result.returncode != 0:
        raise RuntimeError(f"ip {' '.join(args)}: {result.stderr.strip()}")


class NetworkLab:
    """Hosts (network namespaces) joined by a bridge in a namespace of its own.

    Args:
        hosts: Host names (letters and digits), each given a namespace and an address.
    """

    def __init__(self, hosts: Sequence[str]) -> None:
        if len(set(hosts)) != len(hosts) or not hosts:
            raise ValueError(f"host names must be distinct and at least one: {hosts!r}")
        number = next(_labs)
        tag = f"sar{os.getpid()}l{number}"
        self._bridge_ns = f"{tag}br"
        self._namespaces = {host: f"{tag}{host}" for host in hosts}
        self._addresses = {host: f"{SUBNET_PREFIX}{i}" for i, host in enumerate(hosts, 1)}
        # Interface names have at most 15 characters: number them.
        self._ports = {host: f"v{os.getpid() % 100000}l{number % 100}x{i}"
                       for i, host in enumerate(hosts)}
        self._made: list[str] = []

    def address(self, host: str) -> str:
        """The host's IPv4 address on the bridge."""
        return self._addresses[host]

    def enter(self, host: str) -> list[str]:
        """The command prefix that runs a program in ``host``'s namespace."""
        return ["ip", "netns", "exec", self._namespaces[host]]

    def ros_env(self, host: str) -> dict[str, str]:
        """ROS discovery settings for a process in ``host``: loopback plus the other hosts."""
        peers = ";".join(a for h, a in self._addresses.items() if h != host)
        # Fast DDS: UDP only, so no shared-memory segment can join two hosts.
        return {"ROS_AUTOMATIC_DISCOVERY_RANGE": "LOCALHOST", "ROS_STATIC_PEERS": peers,
                "FASTDDS_BUILTIN_TRANSPORTS": "UDPv4"}

    def bridge_bytes(self) -> int:
        """Bytes the bridge has forwarded so far (received on its ports)."""
        total = 0
        for port in self._ports.values():
            result = subprocess.run(
                ["ip", "netns", "exec", self._bridge_ns, "cat",
                 f"/sys/class/net/{port}/statistics/rx_bytes"],
                capture_output=True, text=True, check=True)
            total += int(result.stdout)
        return total

    def __enter__(self) -> NetworkLab:
        try:
            self._create()
        except Exception:
            self.close()
            raise
        return self

    def _create(self) -> None:
        _ip("netns", "add", self._bridge_ns)
        self._made.append(self._bridge_ns)
        _ip("-n", self._bridge_ns, "link", "add", "br0", "type", "bridge")
        _ip("-n", self._bridge_ns, "link", "set", "br0", "up")
        for host, namespace in self._namespaces.items():
            _ip("netns", "add", namespace)
            self._made.append(namespace)
            port = self._ports[host]
            # Both ends are made inside the bridge's namespace, never in the machine's.
            _ip("-n", self._bridge_ns, "link", "add", port, "type", "veth",
                "peer", "name", f"{port}h")
            _ip("-n", self._bridge_ns, "link", "set", f"{port}h", "netns", namespace)
            _ip("-n", self._bridge_ns, "link", "set", port, "master", "br0")
            _ip("-n", self._bridge_ns, "link", "set", port, "up")
            _ip("-n", namespace, "link", "set", f"{port}h", "name", "eth0")
            _ip("-n", namespace, "addr", "add", f"{self._addresses[host]}/24", "dev", "eth0")
            _ip("-n", namespace, "link", "set", "eth0", "up")
            _ip("-n", namespace, "link", "set", "lo", "up")

    def close(self) -> None:
        """Delete every namespace the lab made (their interfaces go with them)."""
        for namespace in reversed(self._made):
            subprocess.run(["ip", "netns", "delete", namespace], check=False,
                           capture_output=True)
        self._made.clear()

    def namespaces(self) -> list[str]:
        """The names of the namespaces the lab holds now."""
        return list(self._made)

    def __exit__(self, exc_type: type[BaseException] | None, exc: BaseException | None,
                 tb: TracebackType | None) -> None:
        self.close()


def machine_namespaces() -> set[str]:
    """The network namespaces ``ip netns`` knows on this machine."""
    folder = Path("/var/run/netns")
    return {p.name for p in folder.iterdir()} if folder.is_dir() else set()
