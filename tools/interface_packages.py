"""Step 5 of the set-up: our interface packages, and the stand-ins, built into the venv.

Each package is CMake-built (C and Python code only) into the venv, or copied from the
per-user build cache (``build_cache.py``) when built before with the same inputs.
"""

from __future__ import annotations

import os
import shutil
import time
from pathlib import Path

from build_cache import build_key, entry_path, install_entry, keep
from ros_overlay import NO_CPP_HOOK
from setup_base import (
    PACKAGE,
    ROOT,
    SetupError,
    Stamps,
    compiler_cache,
    digest,
    files_under,
    importable,
    log,
    run,
    venv_python,
)
from sourced_ros import SourcedRos, interface_build_env

#: The stand-ins for nav2_msgs and tf2_msgs (interfaces/stand_ins), where no real one is.
STAND_INS = ("nav2_msgs", "tf2_msgs")
#: Our interface packages, built from interfaces/ in this order.
OWN_INTERFACES = ("sar_interfaces", "sar_fleet_interfaces", "tutorial_interfaces")


def build_interface_package(venv: Path, source: Path, stamps: Stamps,
                            sourced: SourcedRos | None = None) -> None:
    """Install one ament_cmake interface package into the venv, from the cache or a build.

    A build (CMake configure, build, install) is kept in the interface build cache; a later
    venv needing the same build copies it from there. An entry that does not install an
    importable package is removed and the package built again.
    """
    key = digest(files_under(source), stamps.data.get("requirements", ""))
    step = f"interface:{source.name}"
    if stamps.done(step, key) and importable(venv, source.name):
        return
    env = interface_build_env(venv, sourced)
    prefixes = env["CMAKE_PREFIX_PATH"].split(os.pathsep)  # the venv first
    options = ["-DBUILD_TESTING=OFF", "-DCMAKE_BUILD_TYPE=Release"]
    ours = [p.name for p in source.parent.iterdir() if (p / "package.xml").exists()]
    cache_key = build_key(source, venv_python(venv), env, options=options,
                          inputs=[NO_CPP_HOOK], exclude=[*ours, PACKAGE])
    entry = entry_path(source.name, cache_key)
    if install_entry(entry, prefixes, lambda: importable(venv, source.name)):
        log(f"{source.name} from the build cache (key {cache_key[:12]})")
        stamps.mark(step, key)
        return
    log(f"building interface package {source.name}")
    started = time.monotonic()
    installed = cmake_install(venv, source, env, options)
    if not importable(venv, source.name):
        raise SetupError(f"{source.name} was built but `import {source.name}` still fails")
    log(f"  {source.name} ready in {time.monotonic() - started:.1f} s")
    keep(entry, installed, prefixes)
    stamps.mark(step, key)


def cmake_install(venv: Path, source: Path, env: dict[str, str], options: list[str]) -> Path:
    """Configure, build and install an ament_cmake package into the venv; its install manifest.

    Args:
        venv: The venv (the install prefix).
        source: The package's folder.
        env: The build's environment (``CMAKE_PREFIX_PATH`` lists the venv first).
        options: CMake options besides the paths.
    """
    build = venv / ".sar-build" / source.name
    shutil.rmtree(build, ignore_errors=True)  # a failed earlier configure must not linger
    # The compiles read the build tree and the prefixes (generated code, headers): their
    # common folder is the cache's base, unless only "/" holds them all.
    prefixes = env["CMAKE_PREFIX_PATH"].split(os.pathsep)
    launcher, cache_env = compiler_cache(Path(os.path.commonpath([str(venv), *prefixes])))
    env = {**env, **cache_env}
    run(["cmake", "-S", source, "-B", build, f"-DPython3_EXECUTABLE={venv_python(venv)}",
         *options, f"-DCMAKE_INSTALL_PREFIX={venv}",
         f"-DCMAKE_PROJECT_INCLUDE={NO_CPP_HOOK}", *launcher],  # C and Python code only
        what=f"configuring {source.name}", env=env)
    run(["cmake", "--build", build, "--parallel", str(os.cpu_count() or 2)],
        what=f"building {source.name}", env=env)
    run(["cmake", "--install", build], what=f"installing {source.name}", env=env)
    return build / "install_manifest.txt"


def build_interfaces(venv: Path, stamps: Stamps, provided: set[str] = frozenset(),
                     sourced: SourcedRos | None = None) -> None:
    """Build our interface packages, and the stand-ins only where the real ones are missing.

    Ours: sar_interfaces (the event stream and the search-and-rescue servers'),
    sar_fleet_interfaces (the search-and-rescue fleet's coordinator) and
    tutorial_interfaces (the plugin tutorial's Countdown action, a user's own small
    interface package).

    Args:
        venv: The venv.
        stamps: Its stamps.
        provided: Packages the ROS 2 overlay built: their stand-ins are never built.
        sourced: The sourced ROS 2 Jazzy to build against, if any.
    """
    for name in STAND_INS:
        source = ROOT / "interfaces" / "stand_ins" / name
        if name in provided:
            stamps.data.pop(f"interface:{name}", None)  # the real one replaced it
            continue
        if stamps.data.get(f"interface:{name}") is None and importable(venv, name):
            continue  # a real installation provides it: never shadow it
        build_interface_package(venv, source, stamps, sourced)
    for name in OWN_INTERFACES:
        build_interface_package(venv, ROOT / "interfaces" / name, stamps, sourced)
