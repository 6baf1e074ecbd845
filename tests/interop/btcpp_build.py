"""Build BehaviorTree.CPP (from the shared ROS overlay sources) and the checker, once, cached.

The library is configured as plain CMake (no ament, no Groot2/ZeroMQ, no SQLite, no
examples or tests) and installed into a cache folder keyed by a digest of its sources, so
the ~2 min build happens once per machine; the small checker program is keyed by its own
sources and the library's key. An exclusive ``flock`` keeps concurrent runs from building
the same thing twice. Nothing is ever written next to the sources.

Building is set-up work of the test run, never done by a test: ``make test`` runs this
file first (``make test-setup``: ``python tests/interop/btcpp_build.py``), and the tests
only look the programs up (``build=False``), failing with that command when they are
missing. Where no toolchain exists the script says so and the tests skip, with the reason.

Cache folder: ``$SAR_BTCPP_CACHE``, else ``$XDG_CACHE_HOME/sar_framework/btcpp``, else
``~/.cache/sar_framework/btcpp``.
"""

from __future__ import annotations

import fcntl
import hashlib
import os
import shutil
import subprocess
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "tools"))  # setup_base
from ros_overlay import SHARED_SOURCE, local_source
from setup_base import SetupError, cache_home


def _btcpp_source() -> Path:
    """BehaviorTree.CPP in the ROS overlay's source tree, found as the set-up finds it."""
    try:
        overlay = local_source()
    except SetupError:
        overlay = None
    return (overlay or SHARED_SOURCE) / "behaviortree_cpp"


BTCPP_SOURCE = _btcpp_source()
CHECKER_SOURCE = Path(__file__).resolve().parent / "btcpp_checker"
SCRIPT_ORACLE_SOURCE = Path(__file__).resolve().parent / "btcpp_script_oracle"
BTCPP_OPTIONS = (
    "-DBTCPP_GROOT_INTERFACE=OFF", "-DBTCPP_SQLITE_LOGGING=OFF", "-DBTCPP_EXAMPLES=OFF",
    "-DBTCPP_UNIT_TESTS=OFF", "-DBUILD_TESTING=OFF", "-DBTCPP_BUILD_TOOLS=OFF",
    "-DCMAKE_BUILD_TYPE=Release",
)


def missing_toolchain() -> str | None:
    """Return why BT.CPP cannot be built here (one line), or None when it can."""
    for tool in ("cmake", "g++"):
        if shutil.which(tool) is None:
            return f"{tool} is not installed: BehaviorTree.CPP cannot be built"
    if not (BTCPP_SOURCE / "CMakeLists.txt").is_file():
        return f"no BehaviorTree.CPP sources at {BTCPP_SOURCE}"
    return None


def cache_root() -> Path:
    """The folder builds are cached in."""
    if os.environ.get("SAR_BTCPP_CACHE"):
        return Path(os.environ["SAR_BTCPP_CACHE"])
    return cache_home() / "btcpp"


def tree_digest(folder: Path, *extra: str) -> str:
    """A digest of every file's relative path and bytes under ``folder`` (and ``extra``)."""
    digest = hashlib.blake2b(digest_size=12)
    for part in extra:
        digest.update(part.encode())
    for path in sorted(p for p in folder.rglob("*") if p.is_file() and "build" not in p.parts):
        digest.update(str(path.relative_to(folder)).encode() + b"\0")
        digest.update(path.read_bytes())
    return digest.hexdigest()


def _cmake_project(source: Path, target: Path, options: list[str], log: Path) -> None:
    build = target / "build"
    jobs = os.environ.get("SAR_BTCPP_JOBS", "2")
    with log.open("w") as out:
        for argv in (
            ["cmake", "-S", str(source), "-B", str(build), "-G", "Ninja" if shutil.which("ninja")
             else "Unix Makefiles", f"-DCMAKE_INSTALL_PREFIX={target / 'install'}", *options],
            ["cmake", "--build", str(build), "--parallel", jobs],
            ["cmake", "--install", str(build)],
        ):
            done = subprocess.run(argv, stdout=out, stderr=subprocess.STDOUT, check=False)
            if done.returncode != 0:
                raise RuntimeError(f"{' '.join(argv)} failed ({done.returncode}); see {log}")


SETUP_COMMAND = "make test-setup"
"""What builds the programs (``python tests/interop/btcpp_build.py`` does the same)."""


class NotBuiltError(RuntimeError):
    """A program is not in the cache: the test run's set-up did not build it."""


def _cached(key: str, source: Path, options: list[str], *, build: bool) -> Path:
    root = cache_root()
    target = root / key
    if not build:
        if not (target / "done").exists():
            raise NotBuiltError(f"{source.name} is not built for these sources (no "
                                f"{target}): run `{SETUP_COMMAND}` first")
        return target / "install"
    root.mkdir(parents=True, exist_ok=True)
    with (root / f"{key}.lock").open("w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        if not (target / "done").exists():
            shutil.rmtree(target, ignore_errors=True)
            target.mkdir(parents=True)
            _cmake_project(source, target, options, target / "build.log")
            (target / "done").write_text("ok\n")
    return target / "install"


def _build_program(source: Path, name: str, key_prefix: str, *options: str,
                   build: bool) -> Path:
    """BT.CPP and the program in ``source``, built (or reused, or only looked up when
    ``build`` is false); return its executable's path."""
    library_key = "lib-" + tree_digest(BTCPP_SOURCE / "src", *BTCPP_OPTIONS,
                                       (BTCPP_SOURCE / "CMakeLists.txt").read_text(),
                                       tree_digest(BTCPP_SOURCE / "include"))
    library = _cached(library_key, BTCPP_SOURCE, list(BTCPP_OPTIONS), build=build)
    key = key_prefix + tree_digest(source, library_key)
    installed = _cached(key, source, [f"-DCMAKE_PREFIX_PATH={library}",
                                      "-DCMAKE_BUILD_TYPE=Release", *options], build=build)
    return installed / "bin" / name


def build_checker(*, build: bool = True) -> Path:
    """BT.CPP and the checker, built or reused; the checker executable's path.

    Args:
        build: False only looks the checker up.

    Raises:
        NotBuiltError: ``build`` is false and the checker is not in the cache.
    """
    return _build_program(CHECKER_SOURCE, "btcpp_checker", "checker-",
                          f"-DBTCPP_SOURCE_DIR={BTCPP_SOURCE}", build=build)


def build_script_oracle(*, build: bool = True) -> Path:
    """BT.CPP and the script oracle, built or reused; its executable's path.

    Args:
        build: False only looks it up.

    Raises:
        NotBuiltError: ``build`` is false and the oracle is not in the cache.
    """
    return _build_program(SCRIPT_ORACLE_SOURCE, "btcpp_script_oracle", "script-oracle-",
                          build=build)


def main() -> int:
    """Build both programs (the test run's set-up); say why not where no toolchain exists."""
    reason = missing_toolchain()
    if reason is not None:
        print(f"btcpp_build: not built ({reason}); the interop tests that need it will skip")
        return 0
    for program in (build_checker(), build_script_oracle()):
        print(f"btcpp_build: {program}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
