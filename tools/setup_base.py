"""Helpers every set-up step shares: errors, logging, commands, input digests and stamps.

Standard library only: this runs before any venv exists.
"""

from __future__ import annotations

import hashlib
import json
import os
import shutil
import subprocess
from collections.abc import Iterable, Sequence
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
#: The Python package (and ROS package) this project installs.
PACKAGE = "sar_framework"


class SetupError(Exception):
    """A set-up step failed in a way the user must act on; the message says how."""


def log(message: str) -> None:
    """Print one progress line."""
    print(f"[bootstrap] {message}", flush=True)


def run(cmd: Sequence[str | Path], *, what: str, env: dict[str, str] | None = None,
        cwd: Path | None = None) -> str:
    """Run a command, returning its output; raise SetupError with its tail on failure.

    Args:
        cmd: The command.
        what: What the step is doing, for the error message.
        env: Environment (defaults to the current one).
        cwd: Working directory.

    Returns:
        The combined stdout and stderr.
    """
    proc = subprocess.run(
        [str(c) for c in cmd], env=env, cwd=cwd, text=True,
        stdout=subprocess.PIPE, stderr=subprocess.STDOUT, check=False,
    )
    if proc.returncode != 0:
        tail = "\n".join(
            line for line in proc.stdout.splitlines()[-40:]
            if not line.startswith("WARNING: Location")
        )
        raise SetupError(f"{what} failed (exit {proc.returncode}):\n{tail}")
    return proc.stdout


def digest(paths: Iterable[Path], *extra: str) -> str:
    """Hash file contents (and names) plus extra strings: a step's input fingerprint."""
    h = hashlib.sha256()
    for p in sorted(paths):
        h.update(str(p.relative_to(ROOT) if p.is_relative_to(ROOT) else p).encode())
        h.update(p.read_bytes())
    for e in extra:
        h.update(e.encode())
    return h.hexdigest()


def files_under(folder: Path) -> list[Path]:
    """Every file below a folder."""
    return [p for p in folder.rglob("*") if p.is_file()]


class Stamps:
    """Per-venv record of which steps are done for which inputs."""

    def __init__(self, venv: Path) -> None:
        self.path = venv / ".sar-stamps.json"
        try:
            self.data: dict[str, str] = json.loads(self.path.read_text())
        except (OSError, ValueError):
            self.data = {}

    def done(self, step: str, key: str) -> bool:
        """Whether the step already succeeded for these inputs."""
        return self.data.get(step) == key

    def mark(self, step: str, key: str) -> None:
        """Record a step's success (written at once, so a later failure keeps it)."""
        self.data[step] = key
        self.path.write_text(json.dumps(self.data, indent=1, sort_keys=True))


def cache_home() -> Path:
    """The per-user folder our set-up caches live in (``~/.cache/sar_framework``)."""
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base) / "sar_framework"


def compiler_cache(base: Path) -> tuple[list[str], dict[str, str]]:
    """Route a CMake build's C/C++ compiles through ccache, when it is installed.

    A fresh clone builds the same generated C code again (rosidl's type supports are most of
    the ROS overlay's build); ccache turns those compiles into cache hits. Paths below
    ``base`` are rewritten relative to the compiler's folder, so a build in another clone or
    another temporary folder hits too. Without ccache the build is unchanged.

    Args:
        base: The folder holding the build's sources, build tree and install prefix.

    Returns:
        ``(cmake arguments, environment entries)``; both empty without ccache.
    """
    if shutil.which("ccache") is None:
        return [], {}
    env = {"CCACHE_DIR": os.environ.get("CCACHE_DIR") or str(cache_home() / "ccache"),
           # rosidl's generators order some #includes by set iteration: one hash seed makes
           # the generated C the same in every build, so it hits
           "PYTHONHASHSEED": "0"}
    if base != Path(base.anchor):  # a base of "/" would make system headers relative
        env["CCACHE_BASEDIR"] = str(base)
    return (["-DCMAKE_C_COMPILER_LAUNCHER=ccache", "-DCMAKE_CXX_COMPILER_LAUNCHER=ccache"],
            env)


def venv_python(venv: Path) -> Path:
    """The venv's interpreter."""
    return venv / "bin" / "python"


def importable(venv: Path, module: str) -> bool:
    """Whether the venv's interpreter can import a module."""
    return subprocess.run([str(venv_python(venv)), "-c", f"import {module}"],
                          capture_output=True, check=False).returncode == 0
