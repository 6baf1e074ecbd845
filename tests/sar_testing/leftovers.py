"""What a test session leaves behind: files in its temp folder, Fast DDS files in /dev/shm.

The session (the xdist controller, or the only pytest process) gives every process started
after it, its workers and everything they start, a temp folder of the session's own
(``TMPDIR``) and a marker in the environment (:data:`MARKER`). Whatever is in that folder at
the end, this run made and did not remove. A sampler thread notes the Fast DDS
shared-memory files that marked processes map or hold open (``/proc/PID/maps``, ``fd``); at
the end, those that still exist while no live process uses them were left by this run's
processes: by one killed before Fast DDS could clean up, and by clean exits too (Fast DDS
keeps a port's segment, ``fastrtps_portN``, after its last listener closed). Another run's
files are never counted nor touched: they are not in the folder, and its processes do not
carry the marker.

Leftovers are removed once found, so the next run starts clean: the temp folder's are the
tests' fault (each test removes what it made); the Fast DDS files are the middleware's way.
Without workers (no ``-n``) the pytest process keeps the usual temp dir for its own files (pytest's
``tmp_path`` lives there): then only what its children write is in the folder.
"""

from __future__ import annotations

import os
import shutil
import tempfile
import threading
from pathlib import Path

from sar_testing.shm_zombies import PATTERNS, SHM, _in_use

MARKER = "SAR_TEST_SESSION"
"""The environment variable every process of the session carries (its value: the folder)."""
SAMPLE_PERIOD_S = 0.5


class SessionLeftovers:
    """The session's temp folder and its sampler of Fast DDS files.

    Args:
        shm: The shared-memory folder.
    """

    def __init__(self, shm: Path = SHM) -> None:
        self.folder = Path(tempfile.mkdtemp(prefix="sar_tests_"))
        self._shm = shm
        self._tag = f"{MARKER}={self.folder}".encode()
        self._seen: set[str] = set()
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._sample_until_stopped, daemon=True,
                                        name="session-leftovers")

    def start(self, environ: dict[str, str] | os._Environ[str] = os.environ) -> None:
        """Mark ``environ`` (inherited by every process started from now on); start sampling."""
        environ["TMPDIR"] = str(self.folder)
        environ[MARKER] = str(self.folder)
        self._thread.start()

    def _sample_until_stopped(self) -> None:
        while not self._stop.wait(SAMPLE_PERIOD_S):
            self._seen |= self._fastdds_files_of_marked_processes()

    def _fastdds_files_of_marked_processes(self) -> set[str]:
        prefix = f"{self._shm}/"
        found: set[str] = set()
        for proc in Path("/proc").iterdir():
            if not proc.name.isdigit() or int(proc.name) == os.getpid():
                continue
            try:
                if self._tag not in (proc / "environ").read_bytes().split(b"\0"):
                    continue
                paths = [line.split(maxsplit=5)[-1] for line in
                         (proc / "maps").read_text(errors="replace").splitlines()
                         if line.count(" ") >= 5]
                paths += [os.readlink(fd) for fd in (proc / "fd").iterdir()]
            except OSError:  # ended meanwhile, or not ours to read
                continue
            found |= {p[len(prefix):].removesuffix(" (deleted)") for p in paths
                      if p.startswith(prefix)
                      and any(Path(p).match(pattern) for pattern in PATTERNS)}
        return found

    def noted(self) -> set[str]:
        """The Fast DDS file names seen used by the session's processes so far."""
        return set(self._seen)

    def finish(self) -> tuple[list[str], list[str]]:
        """Stop sampling; remove what the session left.

        Returns:
            What was left in the temp folder, and the Fast DDS files of the session's
            processes that were left in /dev/shm (paths, sorted; both removed).
        """
        self._stop.set()
        self._thread.join(timeout=5.0)
        # A nested pytest's basetemp (pytest-of-USER) is kept by pytest's own retention
        # policy, not a test's leftover; it goes with the folder like the rest.
        left = [str(path) for path in sorted(self.folder.iterdir())
                if not path.name.startswith("pytest-of-")]
        shutil.rmtree(self.folder, ignore_errors=True)
        used = _in_use(self._shm)
        removed = []
        for name in sorted(self._seen - used):
            path = self._shm / name
            if path.exists():
                path.unlink(missing_ok=True)
                removed.append(str(path))
        return left, removed
