"""A run's leftovers are found exactly: its temp folder's files, its processes' Fast DDS files."""

from __future__ import annotations

import subprocess
import sys
import time
from pathlib import Path

from sar_testing.leftovers import SessionLeftovers

#: A "ROS process" of the run: a file in its temp dir, a shared-memory segment it maps and
#: leaves when it ends (as a SIGKILLed Fast DDS participant, or a port after a clean exit).
CHILD = """
import mmap, sys, tempfile
from pathlib import Path
tempfile.NamedTemporaryFile(prefix="left_", delete=False).close()
segment = Path(sys.argv[1]) / "fastrtps_0123456789abcdef"
segment.write_bytes(bytes(4096))
with segment.open("r+b") as handle:
    mapped = mmap.mmap(handle.fileno(), 4096)
    print("ready", flush=True)
    sys.stdin.read()
"""


def test_what_the_run_s_processes_left_is_found_and_removed_others_untouched(
        tmp_path: Path) -> None:
    shm = tmp_path / "shm"
    shm.mkdir()
    other_run = shm / "fastrtps_port7413"  # not made by a process of this session
    other_run.write_bytes(b"x")
    leftovers = SessionLeftovers(shm=shm)
    env: dict[str, str] = {"PATH": "/usr/bin:/bin"}
    leftovers.start(env)
    child = subprocess.Popen([sys.executable, "-c", CHILD, str(shm)], env=env,
                             stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)
    try:
        assert child.stdout is not None and child.stdout.readline().strip() == "ready"
        deadline = time.monotonic() + 30.0  # outer safety bound: sampled every 0.5 s
        while "fastrtps_0123456789abcdef" not in leftovers.noted():
            assert time.monotonic() < deadline, (  # outer safety bound
                f"never noted the child's segment: {leftovers.noted()}")
            time.sleep(0.05)
    finally:
        child.communicate(input="", timeout=30)
    folder = leftovers.folder
    left, removed = leftovers.finish()
    assert [Path(p).parent for p in left] == [folder] and Path(left[0]).name.startswith("left_")
    assert removed == [str(shm / "fastrtps_0123456789abcdef")]
    assert not folder.exists() and not (shm / "fastrtps_0123456789abcdef").exists()
    assert other_run.exists(), "another run's file was touched"
