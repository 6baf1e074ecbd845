"""Set-up step: build upstream ROS 2 Jazzy's Python stack into the venv with colcon.

The packages a ROS 2 Jazzy desktop install has and PyPI lacks (launch, launch_ros, ros2cli
and its verbs, tf2 / tf2_ros_py, nav2_msgs, nav2_simple_commander, py_trees_ros, ...) are
built from upstream sources. The source tree is the first of:

1. ``--overlay-src DIR`` or ``SAR_ROS_OVERLAY_SRC=DIR`` (e.g. what ``vcs import`` made);
2. ``../shared/ros-overlay/src`` beside the repository;
3. fetched with vcstool at the pinned commits of ``ros2_jazzy.repos`` (needs network),
   into ``<venv>/.sar-build/overlay/fetched``.

``SAR_ROS_OVERLAY=off`` skips the step, and so does a sourced ROS 2 Jazzy
(``ROS_DISTRO=jazzy`` with launch_ros on ``AMENT_PREFIX_PATH``): the fallbacks or the
system's packages are used then. The needed packages are copied out of the source tree
(nothing is ever written inside it) and built by colcon in parallel, merged into the venv
prefix. Interface packages (nav2_msgs, tf2_msgs, ...) get their C and Python code only, no
C++ (``rosidl_no_cpp.cmake``: rclpy needs none, and it was most of the build).
``nav2_bringup`` (whose CMakeLists needs all of Nav2) has only its launch and params files
installed as a package share. A ``.pth`` hook puts the venv on ``AMENT_PREFIX_PATH``,
so ``.venv/bin/ros2`` and ``ament_index_python`` find every package without sourcing.
"""

from __future__ import annotations

import os
import re
import shutil
import time
from pathlib import Path

from setup_base import (
    ROOT,
    SetupError,
    Stamps,
    compiler_cache,
    digest,
    files_under,
    log,
    run,
    venv_python,
)
from sourced_ros import sourced_ros_prefix

REPOS_FILE = ROOT / "ros2_jazzy.repos"
SHARED_SOURCE = ROOT.parent / "shared" / "ros-overlay" / "src"
#: Built by colcon (BehaviorTree.CPP, launch_testing and friends are not needed here).
PACKAGES = (
    "composition_interfaces", "geographic_msgs", "launch", "launch_ros", "launch_xml",
    "launch_yaml", "nav2_common", "nav2_msgs", "nav2_simple_commander", "py_trees_ros",
    "py_trees_ros_interfaces", "ros2action", "ros2cli", "ros2interface", "ros2launch",
    "ros2lifecycle", "ros2node", "ros2param", "ros2pkg", "ros2run", "ros2service",
    "ros2topic", "rosidl_runtime_py", "tf2", "tf2_msgs", "tf2_py", "tf2_ros_py",
)
#: Installed as data only: package -> folders copied to share/<package>.
DATA_PACKAGES = {"nav2_bringup": ("launch", "params")}
AMENT_HOOK = "sar_ament_prefix.pth"
#: CMAKE_PROJECT_INCLUDE for interface packages: C and Python code only, no C++ (see it).
NO_CPP_HOOK = Path(__file__).resolve().parent / "rosidl_no_cpp.cmake"
_NAME = re.compile(r"<name>\s*([A-Za-z0-9_]+)\s*</name>")


def locate_packages(root: Path, names: set[str]) -> dict[str, Path]:
    """Find ROS packages by name below ``root`` (a folder with package.xml is not entered).

    Args:
        root: A source tree (a colcon workspace's ``src`` or a ``vcs import`` folder).
        names: The package names wanted.

    Returns:
        Name -> package folder, for every wanted package found.
    """
    found: dict[str, Path] = {}
    for folder, dirs, files in os.walk(root):
        dirs[:] = sorted(d for d in dirs if not d.startswith("."))
        if "COLCON_IGNORE" in files:
            dirs[:] = []
            continue
        if "package.xml" in files:
            dirs[:] = []
            match = _NAME.search((Path(folder) / "package.xml").read_text(errors="replace"))
            if match and match.group(1) in names:
                found.setdefault(match.group(1), Path(folder))
    return found


def fetch_sources(venv: Path, repos_file: Path, dest: Path) -> Path:
    """Clone every repository of a vcstool ``.repos`` file at its pinned version.

    Args:
        venv: The venv holding vcstool.
        repos_file: The ``.repos`` file.
        dest: Where the repositories go (re-used: vcs updates what is there).

    Returns:
        ``dest``.

    Raises:
        SetupError: A repository could not be fetched or checked out.
    """
    dest.mkdir(parents=True, exist_ok=True)
    log(f"fetching ROS 2 sources listed in {repos_file.name} into {dest}")
    env = dict(os.environ, GIT_TERMINAL_PROMPT="0")
    run([venv / "bin" / "vcs", "import", "--input", repos_file, "--force", "--retry", "1",
         dest], what=f"vcs import {repos_file.name}", env=env)
    return dest


def local_source(explicit: Path | None = None) -> Path | None:
    """The overlay source tree given or beside the repository; None when there is neither.

    Given is ``explicit``, else ``SAR_ROS_OVERLAY_SRC``; beside the repository is
    ``../shared/ros-overlay/src``.

    Raises:
        SetupError: A source folder was given that does not exist.
    """
    given = explicit or (Path(os.environ["SAR_ROS_OVERLAY_SRC"])
                         if os.environ.get("SAR_ROS_OVERLAY_SRC") else None)
    if given is not None:
        if not given.is_dir():
            raise SetupError(f"ROS overlay source folder not found: {given}")
        return given
    return SHARED_SOURCE if SHARED_SOURCE.is_dir() else None


def find_source(venv: Path, explicit: Path | None, stamps: Stamps,
                repos_file: Path = REPOS_FILE) -> Path | None:
    """Return the overlay source tree to build, or None to stay on the fallbacks."""
    local = local_source(explicit)
    if local is not None:
        return local
    fetched = venv / ".sar-build" / "overlay" / "fetched"
    key = digest([repos_file])
    if stamps.done("overlay-fetch", key):
        return fetched
    if stamps.done("overlay-fetch-failed", key):
        return None  # tried for this .repos file: do not pay a network timeout every run
    try:
        fetch_sources(venv, repos_file, fetched)
    except SetupError as err:
        stamps.mark("overlay-fetch-failed", key)
        log(f"no ROS 2 source tree and the fetch failed; using the fallbacks "
            f"(--overlay-src DIR to build one): {last_line(str(err))}")
        return None
    stamps.mark("overlay-fetch", key)
    return fetched


def last_line(text: str) -> str:
    """The last non-blank line of a message."""
    return next((line for line in reversed(text.splitlines()) if line.strip()), text)


def install_ament_hook(venv: Path) -> None:
    """Put the venv on ``AMENT_PREFIX_PATH`` in every interpreter of the venv."""
    site = next((venv / "lib").glob("python3*/site-packages"))
    hook = site / AMENT_HOOK
    text = ("import os, sys; p = [e for e in os.environ.get('AMENT_PREFIX_PATH', '')"
            ".split(os.pathsep) if e]; sys.prefix in p or os.environ.__setitem__("
            "'AMENT_PREFIX_PATH', os.pathsep.join([sys.prefix, *p]))\n")
    if not hook.exists() or hook.read_text() != text:
        hook.write_text(text)


def installed(venv: Path, names: set[str]) -> bool:
    """Whether every package has its ament index marker in the venv."""
    index = venv / "share" / "ament_index" / "resource_index" / "packages"
    return all((index / name).exists() for name in names)


def build_overlay(venv: Path, stamps: Stamps, source: Path) -> set[str]:
    """Build the overlay packages found in ``source`` into the venv; return their names.

    Raises:
        SetupError: A package is missing from the tree or failed to build.
    """
    wanted = wanted_names()
    found = locate_packages(source, wanted)
    missing = sorted(wanted - set(found))
    if missing:
        raise SetupError(f"{source} lacks the ROS packages {', '.join(missing)} "
                         f"(see {REPOS_FILE.name} for where they come from)")
    key = digest([f for folder in found.values() for f in files_under(folder)],
                 stamps.data.get("requirements", ""), *sorted(found))
    if stamps.done("overlay", key) and installed(venv, wanted):
        return wanted
    work = venv / ".sar-build" / "overlay"
    staged = work / "src"
    shutil.rmtree(staged, ignore_errors=True)
    for name in PACKAGES:  # a copy: colcon and setuptools never write into the source tree
        shutil.copytree(found[name], staged / name, symlinks=True)
    workers = str(os.cpu_count() or 2)
    log(f"building {len(PACKAGES)} ROS 2 Jazzy packages from {source} with colcon "
        f"({workers} in parallel; a few minutes the first time)")
    launcher, cache_env = compiler_cache(venv)  # sources, build and prefix: all in the venv
    env = dict(os.environ, CMAKE_PREFIX_PATH=str(venv), AMENT_PREFIX_PATH=str(venv),
               COLCON_HOME=str(work / "colcon-home"), **cache_env)
    env["PATH"] = f"{venv / 'bin'}{os.pathsep}{env.get('PATH', '')}"
    started = time.monotonic()
    run([venv / "bin" / "colcon", "--log-base", work / "log", "build",
         "--base-paths", staged, "--build-base", work / "build", "--install-base", venv,
         "--merge-install", "--executor", "parallel", "--parallel-workers", workers,
         "--event-handlers", "console_cohesion-", "console_stderr-",
         "--cmake-args", "-DBUILD_TESTING=OFF", f"-DPython3_EXECUTABLE={venv_python(venv)}",
         "-DCMAKE_BUILD_TYPE=Release", f"-DCMAKE_PROJECT_INCLUDE={NO_CPP_HOOK}", *launcher],
        what="colcon build of the ROS 2 overlay", env=env)
    for name, folders in DATA_PACKAGES.items():
        install_data_package(venv, found[name], name, folders)
    log(f"  ROS 2 overlay ready in {time.monotonic() - started:.1f} s")
    stamps.mark("overlay", key)
    return wanted


def install_data_package(venv: Path, source: Path, name: str, folders: tuple[str, ...]) -> None:
    """Install a package's data folders and package.xml as ``share/<name>``, indexed."""
    share = venv / "share" / name
    shutil.rmtree(share, ignore_errors=True)
    share.mkdir(parents=True)
    shutil.copy2(source / "package.xml", share / "package.xml")
    for folder in folders:
        shutil.copytree(source / folder, share / folder)
    marker = venv / "share" / "ament_index" / "resource_index" / "packages" / name
    marker.parent.mkdir(parents=True, exist_ok=True)
    marker.touch()


def ensure_ros_stack(venv: Path, stamps: Stamps, explicit: Path | None) -> set[str]:
    """The whole step: return the names of the packages the overlay provides (may be none)."""
    install_ament_hook(venv)
    if os.environ.get("SAR_ROS_OVERLAY", "").lower() in ("off", "0", "no"):
        return set()
    if sourced_ros_prefix() is not None and explicit is None:
        return set()  # the sourced ROS provides these packages (tools/sourced_ros.py)
    source = find_source(venv, explicit, stamps)
    if source is None:
        # Built from a tree that is gone since: the real packages are still installed.
        return wanted_names() if "overlay" in stamps.data and installed(venv, wanted_names()) \
            else set()
    return build_overlay(venv, stamps, source)


def wanted_names() -> set[str]:
    """Every package the overlay installs."""
    return set(PACKAGES) | set(DATA_PACKAGES)
