"""tools/bootstrap.py: idempotent when warm, clear messages when the machine lacks something.

A failed step must leave the next run able to finish: no half-built venv that later
fails obscurely.
"""

from __future__ import annotations

import importlib.util
import json
import os
import shutil
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path
from types import ModuleType

import pytest

ROOT = Path(__file__).resolve().parent.parent.parent
BOOTSTRAP = ROOT / "tools" / "bootstrap.py"


def load_module(path: Path, name: str = "") -> ModuleType:
    spec = importlib.util.spec_from_file_location(name or f"{path.stem}_under_test", path)
    assert spec and spec.loader
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def load_bootstrap() -> ModuleType:
    return load_module(BOOTSTRAP, "bootstrap_under_test")


def run_bootstrap(*args: str, env: dict[str, str]) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, str(BOOTSTRAP), *args], env=env, text=True, capture_output=True,
        timeout=300, check=False,
    )


def test_warm_run_does_nothing_and_says_ready() -> None:
    # make test ran the bootstrap just before pytest, so every step is stamped.
    done = run_bootstrap(env=dict(os.environ))
    assert done.returncode == 0, done.stderr
    assert "environment ready" in done.stdout
    for busy in ("installing", "building", "creating"):
        assert busy not in done.stdout


def test_missing_system_tools_are_named_and_no_venv_is_made(tmp_path: Path) -> None:
    bare = tmp_path / "bin"
    bare.mkdir()
    (bare / "python3.11").symlink_to(sys.executable)  # only an interpreter on PATH
    venv = tmp_path / "venv"
    env = dict(os.environ, PATH=str(bare), SAR_NO_APT="1", SAR_VENV=str(venv))
    done = run_bootstrap("--no-compat", env=env)
    assert done.returncode == 1
    assert ("missing system tools: cmake, gcc, g++, make, graphviz, chromium, chromium-driver"
            in done.stderr)
    assert "apt-get install" in done.stderr
    assert "Traceback" not in done.stderr
    assert not venv.exists()


def test_an_optional_tool_apt_cannot_install_leaves_the_set_up_going(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
        ) -> None:
    bootstrap = load_bootstrap()
    tools = tmp_path / "bin"  # every required tool, no ccache, an apt-get that fails
    tools.mkdir()
    for command in bootstrap.SYSTEM_TOOLS:
        found = shutil.which(command)
        if found is None:
            pytest.skip(f"{command} is not installed here")
        (tools / command).symlink_to(found)
    (tools / "apt-get").write_text("#!/bin/sh\necho 'E: Unable to locate package' >&2\n"
                                   "exit 100\n")
    (tools / "apt-get").chmod(0o755)
    monkeypatch.setenv("PATH", str(tools))
    monkeypatch.delenv("SAR_NO_APT", raising=False)
    monkeypatch.setattr(bootstrap.os, "geteuid", lambda: 0)  # as root, apt-get is tried
    bootstrap.ensure_system_tools(sys.executable)  # no SetupError: ccache is optional
    said = capsys.readouterr()
    assert "ccache" in said.out + said.err and "without it" in said.out + said.err


def test_python_too_old_is_refused(monkeypatch: pytest.MonkeyPatch) -> None:
    bootstrap = load_bootstrap()
    monkeypatch.setattr(bootstrap.sys, "version_info", (3, 9, 18, "final", 0))
    with pytest.raises(bootstrap.SetupError, match="too old"):
        bootstrap.find_python()


def test_python_other_than_311_without_311_explains(monkeypatch: pytest.MonkeyPatch) -> None:
    bootstrap = load_bootstrap()
    monkeypatch.setattr(bootstrap.sys, "version_info", (3, 12, 1, "final", 0))
    monkeypatch.setattr(bootstrap.shutil, "which", lambda _name: None)
    with pytest.raises(bootstrap.SetupError, match=r"built for CPython 3\.11 only"):
        bootstrap.find_python()


@dataclass
class OfflineRun:
    """The bootstrap run offline over a half-made venv: what it said and left."""

    venv: Path
    done: subprocess.CompletedProcess[str]
    stamps: dict[str, str]  # the venv's stamps just after the run


@pytest.fixture(scope="module")
def offline_over_a_broken_venv(tmp_path_factory: pytest.TempPathFactory) -> OfflineRun:
    """One bootstrap run for two facts: a broken venv is replaced, then pip cannot download.

    Both need a venv made from scratch (most of the run's cost): one is made, not two.
    """
    venv = tmp_path_factory.mktemp("offline") / "venv"
    (venv / "bin").mkdir(parents=True)
    (venv / "bin" / "python").write_text("#!/bin/sh\nexit 1\n")  # a half-made venv
    (venv / "bin" / "python").chmod(0o755)
    offline = dict(
        os.environ, SAR_VENV=str(venv), PIP_INDEX_URL="http://127.0.0.1:9/simple",
        PIP_EXTRA_INDEX_URL="", PIP_FIND_LINKS="", PIP_RETRIES="0", PIP_TIMEOUT="2",
        PIP_CONSTRAINT="",
    )
    done = run_bootstrap("--no-compat", env=offline)
    stamps_file = venv / ".sar-stamps.json"
    stamps = json.loads(stamps_file.read_text()) if stamps_file.exists() else {}
    return OfflineRun(venv, done, stamps)


def test_unreachable_index_is_explained_and_the_next_run_can_finish(
        offline_over_a_broken_venv: OfflineRun) -> None:
    venv, done = offline_over_a_broken_venv.venv, offline_over_a_broken_venv.done
    assert done.returncode == 1, done.stdout + done.stderr
    assert "could not download packages from the Python package index" in done.stderr
    assert "Traceback (most recent call last)" not in done.stderr.split("pip install")[0]
    # The venv itself is whole; the failed step is not stamped, so the next run redoes it.
    assert (venv / "bin" / "python").exists()
    assert "requirements" not in offline_over_a_broken_venv.stamps


def test_broken_venv_is_replaced(offline_over_a_broken_venv: OfflineRun, tmp_path: Path
                                 ) -> None:
    venv, done = offline_over_a_broken_venv.venv, offline_over_a_broken_venv.done
    assert f"replacing virtual environment {venv}" in done.stdout, done.stdout + done.stderr
    assert subprocess.run([str(venv / "bin" / "python"), "-c", "pass"],
                          check=False).returncode == 0
    # The replacement is a whole venv: the set-up's venv step finishes on it.
    bootstrap = load_bootstrap()
    req = tmp_path / "empty.txt"
    req.write_text("# nothing\n")
    stamps = bootstrap.ensure_venv(sys.executable, venv, [req])
    assert stamps.done("requirements", bootstrap.digest([req], "system-site=False"))
    assert subprocess.run([str(venv / "bin" / "python"), "-c", "pass"],
                          check=False).returncode == 0


def test_over_a_sourced_ros_only_the_requirements_it_lacks_are_installed(tmp_path) -> None:
    load_bootstrap()  # puts tools/ on sys.path
    import sourced_ros

    req = tmp_path / "python.txt"
    req.write_text("# pins\nPyYAML==6.0.3\npy_trees==2.6.0  # ROS has 2.2\n"
                   "jsonschema==4.26.0\nrich==15.0.0\n\n")
    provided = {sourced_ros.normalised(n) for n in ("pyyaml", "py-trees", "numpy")}
    out = sourced_ros.requirements_not_provided([req], provided, tmp_path / "o" / "r.txt")
    assert out.read_text() == "jsonschema==4.26.0\nrich==15.0.0\n"


# --- step 4: the ROS 2 overlay (tools/ros_overlay.py) -----------------------------------

def load_interface_packages() -> ModuleType:
    """tools/interface_packages.py, the set-up's interface step, as bootstrap imports it."""
    load_bootstrap()  # puts tools/ on sys.path
    import interface_packages

    return interface_packages


def load_overlay() -> ModuleType:
    load_bootstrap()  # puts tools/ on sys.path
    import ros_overlay

    return ros_overlay


def git(*args: str, cwd: Path) -> str:
    return subprocess.run(["git", *args], cwd=cwd, check=True, text=True,
                          capture_output=True).stdout.strip()


def make_upstream(tmp_path: Path) -> tuple[Path, str]:
    """A local git repository standing in for an upstream one: two commits, pin the first."""
    upstream = tmp_path / "upstream"
    (upstream / "demo_msgs").mkdir(parents=True)
    git("init", "-q", "-b", "main", cwd=upstream)
    package_xml = upstream / "demo_msgs" / "package.xml"
    package_xml.write_text("<package format='3'><name>demo_msgs</name>"
                           "<version>1.0.0</version></package>\n")
    git("add", ".", cwd=upstream)
    git("-c", "user.name=t", "-c", "user.email=t@example.com", "commit", "-qm", "v1",
        cwd=upstream)
    pinned = git("rev-parse", "HEAD", cwd=upstream)
    package_xml.write_text(package_xml.read_text().replace("1.0.0", "2.0.0"))
    git("-c", "user.name=t", "-c", "user.email=t@example.com", "commit", "-qam", "v2",
        cwd=upstream)
    return upstream, pinned


def test_repos_file_pins_every_overlay_repository_to_a_commit() -> None:
    import yaml

    repos = yaml.safe_load((ROOT / "ros2_jazzy.repos").read_text())["repositories"]
    assert len(repos) == 11
    for name, entry in repos.items():
        assert entry["type"] == "git", name
        assert entry["url"].startswith("https://github.com/"), name
        assert len(entry["version"]) == 40 and int(entry["version"], 16) >= 0, name


def test_fetch_checks_out_the_pinned_commit_of_a_repos_file(tmp_path: Path) -> None:
    overlay = load_overlay()
    upstream, pinned = make_upstream(tmp_path)
    repos = tmp_path / "test.repos"
    repos.write_text(f"repositories:\n  demo:\n    type: git\n    url: file://{upstream}\n"
                     f"    version: {pinned}\n")
    dest = overlay.fetch_sources(Path(sys.prefix), repos, tmp_path / "fetched")
    assert git("rev-parse", "HEAD", cwd=dest / "demo") == pinned
    found = overlay.locate_packages(dest, {"demo_msgs", "absent"})
    assert found == {"demo_msgs": dest / "demo" / "demo_msgs"}
    assert "1.0.0" in (found["demo_msgs"] / "package.xml").read_text()  # not the newer one


def test_a_failed_fetch_falls_back_once_and_is_not_retried(tmp_path: Path,
                                                           monkeypatch: pytest.MonkeyPatch,
                                                           capsys: pytest.CaptureFixture
                                                           ) -> None:
    overlay = load_overlay()
    monkeypatch.setattr(overlay, "SHARED_SOURCE", tmp_path / "no-shared")
    repos = tmp_path / "gone.repos"
    repos.write_text(f"repositories:\n  demo:\n    type: git\n    url: file://{tmp_path}/nope\n"
                     "    version: 0123456789012345678901234567890123456789\n")
    venv = tmp_path / "venv"
    venv.mkdir()
    (venv / "bin").mkdir()
    (venv / "bin" / "vcs").symlink_to(Path(sys.prefix) / "bin" / "vcs")
    stamps = overlay.Stamps(venv)
    assert overlay.find_source(venv, None, stamps, repos) is None
    assert "using the fallbacks" in capsys.readouterr().out
    assert overlay.find_source(venv, None, stamps, repos) is None
    assert "fetching" not in capsys.readouterr().out  # stamped: no second attempt


def test_an_explicit_source_folder_must_exist(tmp_path: Path) -> None:
    overlay = load_overlay()
    with pytest.raises(overlay.SetupError, match="source folder not found"):
        overlay.find_source(tmp_path, tmp_path / "missing", overlay.Stamps(tmp_path))


def test_packages_are_found_by_name_and_colcon_ignore_is_honoured(tmp_path: Path) -> None:
    overlay = load_overlay()
    for folder, name in (("a/x", "tf2"), ("b/ignored/y", "tf2_msgs"), ("c", "launch")):
        (tmp_path / folder).mkdir(parents=True)
        (tmp_path / folder / "package.xml").write_text(f"<package><name>{name}</name></package>")
    (tmp_path / "b" / "COLCON_IGNORE").touch()
    assert overlay.locate_packages(tmp_path, {"tf2", "tf2_msgs", "launch"}) == {
        "tf2": tmp_path / "a" / "x", "launch": tmp_path / "c"}


def test_a_source_tree_lacking_a_package_is_named(tmp_path: Path) -> None:
    overlay = load_overlay()
    with pytest.raises(overlay.SetupError, match=r"lacks the ROS packages .*nav2_msgs"):
        overlay.build_overlay(tmp_path, overlay.Stamps(tmp_path), tmp_path)


def test_stand_ins_are_not_built_where_the_overlay_provides_the_package(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    step = load_interface_packages()
    built: list[str] = []
    monkeypatch.setattr(step, "build_interface_package",
                        lambda _venv, source, _stamps, _sourced: built.append(source.name))
    stamps = step.Stamps(tmp_path)
    stamps.data["interface:nav2_msgs"] = "an old stand-in"
    step.build_interfaces(tmp_path, stamps, {"nav2_msgs", "tf2_msgs"})
    assert built == ["sar_interfaces", "sar_fleet_interfaces", "tutorial_interfaces"]
    assert "interface:nav2_msgs" not in stamps.data


def test_the_venv_is_on_ament_prefix_path_without_sourcing(tmp_path: Path) -> None:
    venv = Path(sys.prefix)
    code = "import os; print(os.environ['AMENT_PREFIX_PATH'])"
    env = {k: v for k, v in os.environ.items() if k != "AMENT_PREFIX_PATH"}
    alone = subprocess.run([sys.executable, "-c", code], env=env, text=True,
                           capture_output=True, check=True).stdout.strip()
    assert alone == str(venv)
    env["AMENT_PREFIX_PATH"] = str(tmp_path)
    both = subprocess.run([sys.executable, "-c", code], env=env, text=True,
                          capture_output=True, check=True).stdout.strip()
    assert both.split(os.pathsep) == [str(venv), str(tmp_path)]


def test_a_missing_executable_link_is_made_again(tmp_path: Path) -> None:
    # ros2 launch finds our executables in <venv>/lib/sar_framework; a warm set-up whose
    # links lack one (a console script added later) must make them again. On a venv of the
    # test's own: unlinking the project's would fail a ros2 launch running meanwhile.
    bootstrap = load_bootstrap()
    venv = tmp_path / "venv"
    (venv / "bin").mkdir(parents=True)
    for script in bootstrap.EXECUTABLES:
        (venv / "bin" / script).write_text("#!/bin/sh\n")
    bootstrap.link_package_share(venv)
    assert bootstrap.package_linked(venv)
    link = venv / "lib" / "sar_framework" / "sar-sim"
    link.unlink()
    assert not bootstrap.package_linked(venv)  # so a warm run installs and links again
    bootstrap.link_package_share(venv)
    assert link.is_symlink() and link.exists() and bootstrap.package_linked(venv)


def test_every_executable_a_mission_or_fleet_starts_is_linked_for_ros2_launch(
        tmp_path: Path) -> None:
    from sar_plugins.sar.app import APP

    from sar_framework.mission.processes import MissionSettings, Robot, mission_processes

    mission = MissionSettings(tree="t.yaml", params_file="", record=str(tmp_path / "r.mcap"))
    fleet = MissionSettings(tree="t.yaml", run_folder=str(tmp_path), fleet_file="f.yaml",
                            robots=(Robot("r1"),), node_kinds=frozenset({"ClaimZone"}))
    started = {p.executable for settings in (mission, fleet)
               for p in mission_processes(settings, [APP])}
    assert "sar-zone-coordinator" in started
    assert started <= set(load_bootstrap().EXECUTABLES)


@pytest.mark.slow
def test_overlay_interface_packages_get_c_and_python_code_only(demo_build: DemoBuild) -> None:
    # tools/rosidl_no_cpp.cmake (CMAKE_PROJECT_INCLUDE of the overlay build) drops the C++
    # generators: a demo interface package gets its C typesupports and Python module, and
    # no C++ typesupport library. A package outside the interface group is left alone.
    build = demo_build.root / "build"
    built = {p.name for p in build.rglob("*.so")}
    assert {"libdemo_msgs__rosidl_generator_c.so", "libdemo_msgs__rosidl_typesupport_c.so",
            "libdemo_msgs__rosidl_typesupport_fastrtps_c.so",
            "libdemo_msgs__rosidl_typesupport_introspection_c.so",
            "libdemo_msgs__rosidl_generator_py.so"} <= built
    assert any(name.startswith("demo_msgs_s__rosidl_typesupport_c.") for name in built)
    assert not [name for name in built if "_cpp" in name]
    assert not list(build.rglob("ping.hpp"))  # no C++ message headers either
    # rclpy's path: the Python module and the C typesupport serialise a message (rmw).
    code = ("from demo_msgs.msg import Ping; from rclpy.serialization import "
            "serialize_message as s, deserialize_message as d; "
            "print(d(s(Ping(text='over DDS')), Ping).text)")
    library_path = os.pathsep.join([str(build), os.environ.get("LD_LIBRARY_PATH", "")])
    env = dict(demo_build.env, PYTHONPATH=str(build / "rosidl_generator_py"),
               LD_LIBRARY_PATH=library_path)
    done = subprocess.run([sys.executable, "-c", code], env=env, text=True,
                          capture_output=True, check=False)
    assert done.stdout.strip() == "over DDS", done.stderr


def test_set_up_leaves_bytecode_for_what_every_mission_process_imports() -> None:
    # make test ran the bootstrap just before pytest. Under PYTHONDONTWRITEBYTECODE no import
    # writes a .pyc: without these, each process compiles the overlay and project again.
    import py_trees_ros.trees
    import sar_plugins.nav2

    import sar_framework.runner.node
    for module in (py_trees_ros.trees, sar_framework.runner.node, sar_plugins.nav2):
        source = Path(module.__file__)
        cached = Path(importlib.util.cache_from_source(str(source)))
        assert cached.exists(), f"no {cached}"
        assert cached.stat().st_mtime >= source.stat().st_mtime, f"{cached} is stale"


def test_bytecode_is_written_even_when_imports_may_not_write_it(tmp_path: Path) -> None:
    bootstrap = load_bootstrap()
    venv = tmp_path / "venv"
    site = venv / "lib" / "python3.11" / "site-packages" / "pkg"
    site.mkdir(parents=True)
    (site / "mod.py").write_text("X = 1\n")
    (site / "broken.py").write_text("def (:\n")  # loses only its own cache
    sources = tmp_path / "src"
    sources.mkdir()
    (sources / "own.py").write_text("Y = 2\n")
    (venv / "bin").mkdir()
    (venv / "bin" / "python").symlink_to(sys.executable)
    stamps = bootstrap.Stamps(venv)
    bootstrap.compile_bytecode(venv, stamps, [sources])
    assert Path(importlib.util.cache_from_source(str(site / "mod.py"))).exists()
    assert Path(importlib.util.cache_from_source(str(sources / "own.py"))).exists()
    assert "bytecode" in stamps.data
    # Stamped: site-packages are not walked again, the sources are.
    (site / "late.py").write_text("Z = 3\n")
    (sources / "new.py").write_text("W = 4\n")
    bootstrap.compile_bytecode(venv, stamps, [sources])
    assert not Path(importlib.util.cache_from_source(str(site / "late.py"))).exists()
    assert Path(importlib.util.cache_from_source(str(sources / "new.py"))).exists()


def demo_interface_package(root: Path) -> Path:
    """A one-message ament_cmake interface package in ``root/demo_msgs``."""
    source = root / "demo_msgs"
    (source / "msg").mkdir(parents=True)
    (source / "msg" / "Ping.msg").write_text("builtin_interfaces/Time stamp\nstring text\n")
    (source / "package.xml").write_text(
        "<package format='3'><name>demo_msgs</name><version>1.0.0</version>"
        "<description>d</description><maintainer email='dev@example.com'>dev</maintainer>"
        "<license>Apache-2.0</license><buildtool_depend>ament_cmake</buildtool_depend>"
        "<depend>builtin_interfaces</depend>"
        "<member_of_group>rosidl_interface_packages</member_of_group>"
        "<export><build_type>ament_cmake</build_type></export></package>\n")
    (source / "CMakeLists.txt").write_text(
        "cmake_minimum_required(VERSION 3.8)\nproject(demo_msgs)\n"
        "find_package(ament_cmake REQUIRED)\nfind_package(rosidl_default_generators REQUIRED)\n"
        "find_package(builtin_interfaces REQUIRED)\n"
        "rosidl_generate_interfaces(${PROJECT_NAME} msg/Ping.msg "
        "DEPENDENCIES builtin_interfaces)\nament_package()\n")
    return source


def cmake_build(source: Path, build: Path, env: dict[str, str], *options: str) -> None:
    """Configure and build an interface package as the overlay does (C and Python only)."""
    for cmd in (["cmake", "-S", str(source), "-B", str(build), "-DBUILD_TESTING=OFF",
                 f"-DPython3_EXECUTABLE={sys.executable}",
                 f"-DCMAKE_PROJECT_INCLUDE={ROOT / 'tools' / 'rosidl_no_cpp.cmake'}",
                 *options],
                ["cmake", "--build", str(build), "--parallel", "2"]):
        done = subprocess.run(cmd, env=env, text=True, capture_output=True, check=False)
        assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]


def ccache_stats(env: dict[str, str]) -> dict[str, str]:
    """``ccache --print-stats`` of the cache ``env`` names, as a dict."""
    stats = subprocess.run(["ccache", "--print-stats"], env=env, text=True,
                           capture_output=True, check=True).stdout
    return dict(line.split("\t") for line in stats.splitlines() if "\t" in line)


@dataclass
class DemoBuild:
    """The demo interface package built once in ``root`` (``root/build``), as the overlay is.

    Attributes:
        root: The first clone: ``root/demo_msgs`` built in ``root/build``.
        env: The build's environment, without the compiler cache's entries.
        ccache: The compiler cache of this module's builds; None without ccache.
        cache_env: The compiler cache's environment entries the build had.
        options: The compiler cache's CMake arguments the build had.
        stats: The cache's statistics just after the build (empty without ccache).
    """

    root: Path
    env: dict[str, str]
    ccache: Path | None
    cache_env: dict[str, str]
    options: list[str]
    stats: dict[str, str]


@pytest.fixture(scope="module")
def demo_build(tmp_path_factory: pytest.TempPathFactory) -> DemoBuild:
    """One real build for what the build makes and for the compiler cache's first clone."""
    prefix = Path(sys.prefix)
    if not (prefix / "share" / "rosidl_default_generators").is_dir():
        pytest.skip("no rosidl generators in this venv (a sourced ROS 2 provides them)")
    work = tmp_path_factory.mktemp("demo_build")
    ccache = work / "ccache" if shutil.which("ccache") else None  # this module's own cache
    env = dict(os.environ, CMAKE_PREFIX_PATH=str(prefix), AMENT_PREFIX_PATH=str(prefix),
               PATH=f"{prefix / 'bin'}{os.pathsep}{os.environ['PATH']}")
    root = work / "first_clone"
    setup_base = load_module(ROOT / "tools" / "setup_base.py")
    with pytest.MonkeyPatch.context() as patch:
        if ccache is not None:
            patch.setenv("CCACHE_DIR", str(ccache))
        options, cache_env = setup_base.compiler_cache(root)
    cmake_build(demo_interface_package(root), root / "build", dict(env, **cache_env), *options)
    stats = ccache_stats(dict(env, CCACHE_DIR=str(ccache))) if ccache is not None else {}
    return DemoBuild(root, env, ccache, cache_env, options, stats)


def test_a_build_in_another_folder_compiles_from_the_compiler_cache(
        demo_build: DemoBuild, monkeypatch: pytest.MonkeyPatch) -> None:
    # A fresh clone builds the overlay's generated C again: with ccache (setup_base.
    # compiler_cache) the second build, at another path, compiles nothing itself.
    if demo_build.ccache is None:
        pytest.skip("ccache is not installed (make setup installs it when run as root)")
    assert demo_build.options, "the first clone's build did not go through ccache"
    assert demo_build.cache_env["CCACHE_DIR"] == str(demo_build.ccache)
    assert demo_build.cache_env["CCACHE_BASEDIR"] == str(demo_build.root)
    monkeypatch.setenv("CCACHE_DIR", str(demo_build.ccache))  # the first clone's cache
    setup_base = load_module(ROOT / "tools" / "setup_base.py")
    root = demo_build.root.parent / "second_clone"
    options, cache_env = setup_base.compiler_cache(root)
    assert cache_env["CCACHE_DIR"] == str(demo_build.ccache)
    assert cache_env["CCACHE_BASEDIR"] == str(root)
    cmake_build(demo_interface_package(root), root / "build",
                dict(demo_build.env, **cache_env), *options)
    first, second = demo_build.stats, ccache_stats(dict(demo_build.env, **cache_env))
    compiled = int(first["cache_miss"])
    assert compiled > 5 and int(first["direct_cache_hit"]) == 0, first
    assert int(second["cache_miss"]) == compiled, "the second build compiled something again"
    assert int(second["direct_cache_hit"]) == compiled, second


def test_without_ccache_the_build_is_unchanged(monkeypatch: pytest.MonkeyPatch) -> None:
    setup_base = load_module(ROOT / "tools" / "setup_base.py")
    monkeypatch.setattr(setup_base.shutil, "which", lambda name: None)
    assert setup_base.compiler_cache(ROOT) == ([], {})
