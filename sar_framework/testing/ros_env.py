"""A ROS 2 environment of its own for each test run.

Every run gets ``ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST`` (no traffic leaves loopback)
and a ``ROS_DOMAIN_ID`` nobody else on the machine holds: ids are claimed with an
exclusive ``flock`` on a file in the temp dir, so parallel runs (two developers, CI and a
shell) never see each other's nodes. An id whose DDS ports some process has already bound
(a ``sar-tree run`` or ``ros2 launch`` on a fixed ``ROS_DOMAIN_ID``, which leases nothing)
is skipped too.
"""

from __future__ import annotations

import fcntl
import os
import tempfile
from pathlib import Path
from typing import IO

# Fast DDS maps a domain to UDP ports; 1..101 is safe on Linux with default port ranges.
_DOMAIN_RANGE = range(1, 102)
# The RTPS port mapping (Fast DDS and Cyclone defaults): domain d owns the UDP ports
# 7400 + 250 d ... 7400 + 250 d + 249 (discovery and user traffic of every participant).
_PORT_BASE, _DOMAIN_GAIN = 7400, 250
_UDP_TABLES = (Path("/proc/net/udp"), Path("/proc/net/udp6"))


class DomainLease:
    """An exclusively held ROS domain id, released by :meth:`release`.

    Attributes:
        domain_id: The id this process holds.
    """

    def __init__(self, domain_id: int, handle: IO[str]) -> None:
        self.domain_id = domain_id
        self._handle = handle

    def release(self) -> None:
        """Give the id back."""
        fcntl.flock(self._handle, fcntl.LOCK_UN)
        self._handle.close()


def domains_in_use() -> set[int]:
    """The domain ids whose RTPS ports a process on this machine has bound (Linux).

    Empty where the kernel's UDP tables cannot be read.
    """
    used: set[int] = set()
    for table in _UDP_TABLES:
        try:
            lines = table.read_text().splitlines()[1:]
        except OSError:
            continue
        for line in lines:  # "sl local_address rem_address ...", local as HEXADDR:HEXPORT
            port = int(line.split()[1].rsplit(":", 1)[1], 16)
            if port >= _PORT_BASE:
                used.add((port - _PORT_BASE) // _DOMAIN_GAIN)
    return used


LOCKS_ENV = "SAR_ROS_DOMAIN_LOCKS"
"""Where the lock files are, when set: one folder for the machine, whatever ``TMPDIR`` a
test session gives its processes."""


def lock_folder() -> Path:
    """The machine-wide folder of the domain locks.

    ``$SAR_ROS_DOMAIN_LOCKS``, else the temp dir's ``sar_framework_ros_domains``.
    """
    return Path(os.environ.get(LOCKS_ENV)
                or Path(tempfile.gettempdir()) / "sar_framework_ros_domains")


def lease_domain_id() -> DomainLease:
    """Claim a free ROS domain id for this process: unleased, and no participant on it.

    Returns:
        The lease; keep it alive for as long as the id is used.

    Raises:
        RuntimeError: Every id in the range is held by another run.
    """
    folder = lock_folder()
    folder.mkdir(exist_ok=True)
    start = os.getpid() % len(_DOMAIN_RANGE)  # spread concurrent runs over the range
    ids = list(_DOMAIN_RANGE)
    for domain_id in ids[start:] + ids[:start]:
        if domain_id in domains_in_use():  # read again each time: others start meanwhile
            continue
        handle = (folder / f"{domain_id}.lock").open("w")
        try:
            fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            handle.close()
            continue
        return DomainLease(domain_id, handle)
    raise RuntimeError("no free ROS_DOMAIN_ID: too many test runs at once")


def apply_local_ros_env(domain_id: int) -> None:
    """Set this process's (and its children's) ROS environment to loopback + ``domain_id``."""
    os.environ["ROS_AUTOMATIC_DISCOVERY_RANGE"] = "LOCALHOST"
    os.environ["ROS_DOMAIN_ID"] = str(domain_id)
    os.environ.pop("ROS_STATIC_PEERS", None)
    os.environ.pop("ROS_LOCALHOST_ONLY", None)  # deprecated in Jazzy; RANGE replaces it
    os.environ.setdefault("RMW_IMPLEMENTATION", "rmw_fastrtps_cpp")
    os.environ["PYTHONUNBUFFERED"] = "1"
    os.environ["RCUTILS_COLORIZED_OUTPUT"] = "0"
