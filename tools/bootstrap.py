#!/usr/bin/env python3
"""Set up everything sar_framework needs, on a fresh machine or a warm one.

Run by ``make`` before every target; it does real work only when an input changed::

    1. system tools    cmake, a C/C++ compiler, Graphviz's dot, Python headers
                       (apt-get install when missing and running as root); ccache
                       too when it can be installed, never required
    2. .venv           CPython 3.11 venv with the pinned ROS 2 Jazzy wheels and
                       Python dependencies from requirements/*.txt
    3. cmake fix-up    the wheels' exported CMake files name the build container's
                       include paths; rewrite them to this interpreter's
    4. ROS 2 stack     upstream Jazzy launch, ros2cli, tf2, nav2_msgs, py_trees_ros...
                       built with colcon into the venv (tools/ros_overlay.py), when a
                       source tree is found or can be fetched

With a sourced ROS 2 Jazzy (``/opt/ros/jazzy/setup.bash``) the venv is made with its python3
and sees its packages; steps 3 and 4 and the stand-ins are skipped and only the requirements
it lacks are installed (tools/sourced_ros.py).
    5. interfaces      build interfaces/sar_interfaces, the search-and-rescue fleet's
                       interfaces/sar_fleet_interfaces and the plugin tutorial's
                       interfaces/tutorial_interfaces into the venv; build the
                       stand-ins nav2_msgs / tf2_msgs only where step 4 did not provide
                       the real package and the import fails (tools/
                       interface_packages.py); each comes from the
                       per-user build cache (tools/build_cache.py) when built before
                       with the same inputs, in any venv
    6. project         pip install -e . (console script sar-tree)
    7. .venv-compat    py_trees 2.2.3 (ROS Jazzy's) for the engine's compatibility tests

Each step records a stamp (a hash of its inputs) in ``.venv/.sar-stamps.json`` only after
it succeeded, so a failed or interrupted run leaves the next run able to finish the job.
Only the standard library is used here: this runs before any venv exists.
Environment: ``SAR_VENV`` / ``SAR_COMPAT_VENV`` move the venvs; ``SAR_NO_APT=1`` reports
missing system tools instead of installing them; ``SAR_ROS_OVERLAY_SRC=DIR`` names the ROS 2
source tree (``--overlay-src``) and ``SAR_ROS_OVERLAY=off`` skips step 4;
``SAR_INTERFACE_CACHE=DIR`` moves step 5's build cache.
"""

from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable, Sequence
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))  # the set-up's other modules
from interface_packages import build_interfaces
from ros_overlay import ensure_ros_stack
from setup_base import (
    PACKAGE,
    ROOT,
    SetupError,
    Stamps,
    digest,
    log,
    run,
    venv_python,
)
from sourced_ros import (
    detect_sourced_ros,
    install_library_path_hook,
    provided_distributions,
    requirements_not_provided,
)

REQUIRED_PYTHON = (3, 11)  # the ROS 2 Jazzy wheels on PyPI are built for CPython 3.11 only
WHEELS_PYTHON = ".".join(map(str, REQUIRED_PYTHON))  # "3.11"
PACKAGE_SHARE = ("launch", "config", "maps", "trees")  # share/sar_framework, as setup.py
EXECUTABLES = ("sar-tree", "sar-mission-runner", "sar-detect-survivor-server",
               "sar-report-survivor-server", "sar-sim", "sar-mission-recorder",
               "sar-zone-coordinator")
# Command -> Debian package that provides it.
# chromium and its driver: the studio's browser tests (tests/studio) drive them headless.
SYSTEM_TOOLS = {"cmake": "cmake", "cc": "gcc", "c++": "g++", "make": "make", "dot": "graphviz",
                "chromium": "chromium", "chromedriver": "chromium-driver"}
#: Installed with them when we may, never required: ccache makes a fresh clone's C builds
#: (the ROS overlay's type supports, our interfaces) cache hits (setup_base.compiler_cache).
OPTIONAL_TOOLS = {"ccache": "ccache"}


# ---------------------------------------------------------------- 1. system tools
def find_python() -> str:
    """Return a CPython 3.11 interpreter for the venv, or explain what to install."""
    if sys.version_info[:2] < (3, 10):  # noqa: UP036 - this runs on any system Python
        raise SetupError(
            f"Python {sys.version.split()[0]} is too old: sar_framework needs Python 3.10+ "
            "and the ROS 2 Jazzy wheels need CPython 3.11 (install python3.11)."
        )
    if sys.version_info[:2] == REQUIRED_PYTHON:
        return sys.executable
    found = shutil.which("python3.11")
    if found:
        return found
    raise SetupError(
        f"this is Python {sys.version.split()[0]}; the ROS 2 Jazzy wheels on PyPI are built "
        "for CPython 3.11 only. Install python3.11 (with its venv module and headers) "
        "and run again."
    )


def ensure_system_tools(python: str) -> None:
    """Check cmake, compilers, dot, chromium (+ driver), Python headers; apt-get them as root."""
    missing = [pkg for cmd, pkg in SYSTEM_TOOLS.items() if shutil.which(cmd) is None]
    include = run([python, "-c", "import sysconfig;print(sysconfig.get_paths()['include'])"],
                  what="asking Python for its include dir").strip()
    if not (Path(include) / "Python.h").exists():
        missing.append(f"python{REQUIRED_PYTHON[0]}.{REQUIRED_PYTHON[1]}-dev")
    optional = [pkg for cmd, pkg in OPTIONAL_TOOLS.items() if shutil.which(cmd) is None]
    may_install = os.environ.get("SAR_NO_APT") != "1"  # tests force the message path
    if not (missing or optional):
        return
    if may_install and os.geteuid() == 0 and shutil.which("apt-get"):
        log(f"installing system packages: {' '.join(missing + optional)}")
        env = dict(os.environ, DEBIAN_FRONTEND="noninteractive")
        try:
            run(["apt-get", "update", "-qq"], what="apt-get update", env=env)
            run(["apt-get", "install", "-y", "-qq", *missing, *optional],
                what="apt-get install", env=env)
        except SetupError as err:
            if missing:
                raise
            log(f"could not install {', '.join(optional)} (optional); going on without it: "
                f"{str(err).strip().splitlines()[-1]}")
        return
    if not missing:
        return
    raise SetupError(
        "missing system tools: " + ", ".join(missing)
        + ". Install them (Debian/Ubuntu: sudo apt-get install " + " ".join(missing)
        + ") and run again."
    )


# ---------------------------------------------------------------- 2. venv + wheels
def venv_matches(venv: Path, version: str, system_site: bool) -> bool:
    """Whether ``venv`` runs Python ``version`` and sees system site-packages as wanted."""
    vpy = venv_python(venv)
    if not vpy.exists() or subprocess.run(
            [str(vpy), "-c", f"import sys; assert '%d.%d' % sys.version_info[:2] == '{version}'"],
            capture_output=True, check=False).returncode != 0:
        return False
    config = (venv / "pyvenv.cfg").read_text() if (venv / "pyvenv.cfg").exists() else ""
    return ("include-system-site-packages = true" in config) == system_site


def ensure_venv(python: str, venv: Path, requirements: list[Path], extra: Sequence[str] = (),
                *, version: str = WHEELS_PYTHON, system_site: bool = False
                ) -> Stamps:
    """Create the venv (replacing a broken or different one) and install pinned requirements.

    Args:
        python: The interpreter to make the venv with.
        venv: Where.
        requirements: Pinned requirement files to install.
        extra: More ``pip install`` arguments.
        version: ``python``'s ``major.minor``; a venv of another version is replaced.
        system_site: See the interpreter's own site-packages (a sourced ROS's Debian ones).
    """
    if venv.exists() and not venv_matches(venv, version, system_site):
        log(f"replacing virtual environment {venv} (broken, or made for another set-up)")
        shutil.rmtree(venv)
    if not venv.exists():
        log(f"creating {venv.name} with {python}")
        try:
            run([python, "-m", "venv", *(["--system-site-packages"] if system_site else []),
                 venv], what="creating the virtual environment")
        except SetupError:
            shutil.rmtree(venv, ignore_errors=True)  # never leave a half-made venv behind
            raise
    stamps = Stamps(venv)
    key = digest(requirements, *extra, f"system-site={system_site}")
    if stamps.done("requirements", key):
        return stamps
    log(f"installing pinned packages into {venv.name} ({', '.join(p.name for p in requirements)})")
    args = [venv_python(venv), "-m", "pip", "install", "--disable-pip-version-check", "-q"]
    for req in requirements:
        args += ["-r", req]
    try:
        run([*args, *extra], what="pip install")
    except SetupError as err:
        text = str(err)
        if any(s in text for s in ("NewConnectionError", "Could not fetch", "Temporary failure",
                                   "No matching distribution", "ConnectTimeout")):
            raise SetupError(
                "could not download packages from the Python package index: check the "
                "network or a proxy/mirror (PIP_INDEX_URL), then run again.\n" + text
            ) from None
        raise
    stamps.mark("requirements", key)
    return stamps


# ---------------------------------------------------------------- 3. cmake fix-up
def fix_wheel_cmake_paths(venv: Path, stamps: Stamps) -> None:
    """Rewrite the build container's include paths baked into the wheels' CMake exports."""
    key = stamps.data.get("requirements", "")
    if stamps.done("cmake-paths", key):
        return
    out = run([venv_python(venv), "-c",
               "import sysconfig, numpy; print(sysconfig.get_paths()['include']);"
               " print(numpy.get_include())"], what="locating Python and NumPy headers")
    py_include, np_include = out.strip().splitlines()[-2:]
    replacements = {
        "/opt/python/cp311-cp311/lib/python3.11/site-packages/numpy/_core/include": np_include,
        "/opt/python/cp311-cp311/include/python3.11": py_include,
    }
    count = 0
    for cmake_file in (venv / "share").rglob("*.cmake"):
        text = cmake_file.read_text()
        if "/opt/python/cp311-cp311" not in text:
            continue
        for old, new in replacements.items():
            text = text.replace(old, new)
        cmake_file.write_text(text)
        count += 1
    log(f"rewrote build-container include paths in {count} CMake files")
    stamps.mark("cmake-paths", key)


# ---------------------------------------------------------------- 6. project
def install_project(venv: Path, stamps: Stamps) -> None:
    """Install this project editable (console script ``sar-tree``)."""
    key = digest([ROOT / "pyproject.toml", ROOT / "package.xml"], str(ROOT),
                 *sorted(p.name for p in (ROOT / "launch").glob("*.py")))
    if (stamps.done("project", key) and package_linked(venv)
            and (venv / "share" / PACKAGE / "package.xml").exists()):
        return
    log(f"installing sar_framework (editable) into {venv.name}")
    run([venv_python(venv), "-m", "pip", "install", "--disable-pip-version-check", "-q",
         "--no-deps", "--no-build-isolation", "-e", ROOT], what="pip install -e .")
    link_package_share(venv)
    stamps.mark("project", key)


def package_linked(venv: Path) -> bool:
    """Whether every console script is linked in ``lib/sar_framework`` for ``ros2 launch``."""
    return all((venv / "lib" / PACKAGE / script).exists() for script in EXECUTABLES)


def link_package_share(venv: Path) -> None:
    """Make the venv an ament prefix holding this package, like ``colcon --symlink-install``.

    ``share/sar_framework`` links package.xml and launch/, config/, maps/, trees/ of the
    repository; ``lib/sar_framework`` links the console scripts. So ``ros2 launch
    sar_framework ...`` and ``ros2 run sar_framework ...`` use the working tree.
    """
    share = venv / "share" / PACKAGE
    lib = venv / "lib" / PACKAGE
    for folder in (share, lib):
        shutil.rmtree(folder, ignore_errors=True)
        folder.mkdir(parents=True)
    for name in ("package.xml", *PACKAGE_SHARE):
        (share / name).symlink_to(ROOT / name)
    # ros2 launch walks launch/ without following links: link the files one by one.
    (share / "launch").unlink()
    (share / "launch").mkdir()
    for launch_file in (ROOT / "launch").glob("*.py"):
        (share / "launch" / launch_file.name).symlink_to(launch_file)
    for script in EXECUTABLES:
        (lib / script).symlink_to(venv / "bin" / script)
    marker = venv / "share" / "ament_index" / "resource_index" / "packages" / PACKAGE
    marker.parent.mkdir(parents=True, exist_ok=True)
    marker.touch()


# ---------------------------------------------------------------- 7. bytecode
def compile_bytecode(venv: Path, stamps: Stamps, sources: Sequence[Path] = ()) -> None:
    """Write the ``.pyc`` files of the venv's packages and of ``sources``.

    With ``PYTHONDONTWRITEBYTECODE`` set (as on this machine and many CI images) no import
    writes one, and packages installed from source (the overlay, interfaces, this project)
    ship none: each of a mission's five Python processes would compile them again on every
    start, about 1.3 s of CPU per mission. compileall writes them whatever that variable says.

    Args:
        venv: The venv whose site-packages to compile (once per set of installed inputs).
        stamps: Its stamps.
        sources: Folders compiled on every run (only files changed since are rewritten).
    """
    key = digest([], *(f"{k}={v}" for k, v in sorted(stamps.data.items()) if k != "bytecode"))
    site = [] if stamps.done("bytecode", key) else sorted(venv.glob("lib/python3*/site-packages"))
    folders = site + [folder for folder in sources if folder.is_dir()]
    if not folders:
        return
    done = subprocess.run([venv_python(venv), "-m", "compileall", "-q", "-j", "0", *folders],
                          capture_output=True, text=True, check=False)
    if done.returncode != 0:  # a file that does not compile only loses its cache
        log(f"compileall could not compile every file (imports still work):\n{done.stdout[-600:]}")
    if site:
        stamps.mark("bytecode", key)


def timed(label: str, step: Callable[[], object]) -> None:
    """Run a step, logging how long it took when it took long enough to notice."""
    started = time.monotonic()
    step()
    elapsed = time.monotonic() - started
    if elapsed > 1.0:
        log(f"{label}: {elapsed:.1f} s")


def main(argv: Sequence[str] | None = None) -> int:
    """Run every set-up step; return the exit code."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--venv", type=Path,
                        default=Path(os.environ.get("SAR_VENV", ROOT / ".venv")))
    parser.add_argument("--compat-venv", type=Path,
                        default=Path(os.environ.get("SAR_COMPAT_VENV", ROOT / ".venv-compat")))
    parser.add_argument("--no-compat", action="store_true", help="skip the py_trees 2.2.3 venv")
    parser.add_argument("--overlay-src", type=Path, metavar="DIR",
                        help="ROS 2 Jazzy source tree to build (default: SAR_ROS_OVERLAY_SRC, "
                        "else ../shared/ros-overlay/src, else fetched per ros2_jazzy.repos)")
    args = parser.parse_args(argv)
    started = time.monotonic()
    try:
        sourced = detect_sourced_ros()
        python = sourced.python if sourced is not None else find_python()
        ensure_system_tools(python)
        req = ROOT / "requirements"
        venv = args.venv.resolve()
        if sourced is not None:
            log(f"using the sourced ROS 2 Jazzy at {sourced.prefix} with {python}: "
                "no ROS wheels, no overlay build")
            with tempfile.TemporaryDirectory() as scratch:
                lacking = requirements_not_provided(
                    [req / "python.txt", req / "dev.txt"], provided_distributions(python),
                    Path(scratch) / "requirements-sourced.txt")
                stamps = ensure_venv(python, venv, [lacking], version=sourced.version,
                                     system_site=True)
            install_library_path_hook(venv)
        else:
            main_reqs = [req / "ros.txt", req / "ros-stack.txt", req / "python.txt",
                         req / "dev.txt"]
            stamps = ensure_venv(python, venv, main_reqs)
            fix_wheel_cmake_paths(venv, stamps)
        overlay = args.overlay_src.resolve() if args.overlay_src else None
        provided: set[str] = set()
        timed("ROS 2 stack", lambda: provided.update(ensure_ros_stack(venv, stamps, overlay)))
        timed("interfaces", lambda: build_interfaces(venv, stamps, provided, sourced))
        install_project(venv, stamps)
        sources = [ROOT / "sar_framework", ROOT / "plugins"]
        timed("bytecode", lambda: compile_bytecode(venv, stamps, sources))
        if not args.no_compat:
            compat = args.compat_venv.resolve()
            compat_stamps = ensure_venv(python, compat, [req / "compat.txt"],
                                        **({"version": sourced.version} if sourced else {}))
            install_project(compat, compat_stamps)
            compile_bytecode(compat, compat_stamps)
    except SetupError as err:
        print(f"[bootstrap] error: {err}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print("[bootstrap] interrupted; run again to finish", file=sys.stderr)
        return 130
    log(f"environment ready ({time.monotonic() - started:.1f} s)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
