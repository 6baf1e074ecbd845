"""Remove Fast DDS shared-memory files that no live process uses, before a test run.

A ROS process killed (SIGKILL, or a test run stopped hard) while Fast DDS creates its
shared-memory port leaves a half-made ``/dev/shm/fastrtps_port*`` behind; a later process
given that port hangs forever inside ``rclpy`` node creation, before any timeout of ours
applies (seen with gdb; hundreds of such files had piled up on this machine). Fast DDS's
own ``fastdds shm clean`` removes zombie ports that still have their lock file, not these.

A file is in use while a process maps it or holds it open (``/proc/*/maps``, ``/proc/*/fd``),
which is how every Fast DDS segment, port and named semaphore is used; the others go. Run
it once per test run, before any ROS process starts.
"""

from __future__ import annotations

import os
from pathlib import Path

SHM = Path("/dev/shm")
#: Fast DDS's shared-memory files: segments, ports, their lock files and semaphores.
PATTERNS = ("fastrtps_*", "sem.fastrtps_*")


def _in_use(shm: Path) -> set[str]:
    """Names of files under ``shm`` that a live process maps or holds open."""
    prefix = f"{shm}/"
    used: set[str] = set()
    for proc in Path("/proc").iterdir():
        if not proc.name.isdigit():
            continue
        try:
            for line in (proc / "maps").read_text(errors="replace").splitlines():
                path = line.split(maxsplit=5)[-1] if line.count(" ") >= 5 else ""
                if path.startswith(prefix):
                    used.add(path[len(prefix):].removesuffix(" (deleted)"))
            for fd in (proc / "fd").iterdir():
                target = os.readlink(fd)
                if target.startswith(prefix):
                    used.add(target[len(prefix):])
        except OSError:  # the process ended meanwhile, or is not ours to read
            continue
    return used


def remove_unused_fastdds_files(shm: Path = SHM) -> list[str]:
    """Delete Fast DDS's files under ``shm`` that no live process uses.

    Args:
        shm: The shared-memory folder.

    Returns:
        The names removed.
    """
    if not shm.is_dir():
        return []
    used = _in_use(shm)
    removed = []
    for pattern in PATTERNS:
        for path in shm.glob(pattern):
            if path.name in used:
                continue
            try:
                path.unlink()
            except OSError:  # another user's, or gone meanwhile
                continue
            removed.append(path.name)
    return removed
