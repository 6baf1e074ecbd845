"""tools/build_cache.py: a venv's interface package comes from the build cache, not a build.

The builds here are real (a one-message package against this venv's rosidl), each venv a
fresh one that sees this venv's packages as a sourced ROS would; the cache is a folder of
this test's own (``SAR_INTERFACE_CACHE``), so nothing here hits the user's cache.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import sysconfig
import venv as venv_module
from pathlib import Path

import pytest
from test_bootstrap import ROOT, demo_interface_package, load_bootstrap, load_module

PREFIX = Path(sys.prefix)
SITE = Path(sysconfig.get_paths()["purelib"])
sys.path.insert(0, str(ROOT / "tools"))  # build_cache imports setup_base as bootstrap does
build_cache = load_module(ROOT / "tools" / "build_cache.py")


def fresh_venv(path: Path) -> Path:
    """A venv without pip whose interpreter also sees this venv's packages."""
    venv_module.create(path, symlinks=True)
    site = next((path / "lib").glob("python3*/site-packages"))
    (site / "this_venv.pth").write_text(f"import site; site.addsitedir({str(SITE)!r})\n")
    return path


def set_up(bootstrap, venv: Path, source: Path) -> None:
    """Install ``source`` into ``venv`` as the set-up's interface step does."""
    ros = bootstrap.SourcedRos(prefix=str(PREFIX), python=sys.executable, version="3.11")
    bootstrap.build_interface_package(venv, source, bootstrap.Stamps(venv), ros)


def entries(cache: Path) -> list[Path]:
    return sorted(cache.iterdir()) if cache.exists() else []


@pytest.fixture
def cache(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    if not (PREFIX / "share" / "rosidl_default_generators").is_dir():
        pytest.skip("no rosidl generators in this venv (a sourced ROS 2 provides them)")
    monkeypatch.setenv("SAR_INTERFACE_CACHE", str(tmp_path / "cache"))
    monkeypatch.setenv("CMAKE_PREFIX_PATH", str(PREFIX))
    monkeypatch.setenv("AMENT_PREFIX_PATH", str(PREFIX))
    return tmp_path / "cache"


def round_trip(venv: Path) -> subprocess.CompletedProcess[str]:
    """Serialise a message with the venv's type support, found on the library path only."""
    code = ("from demo_msgs.msg import Ping; from rclpy.serialization import "
            "serialize_message as s, deserialize_message as d; "
            "print(d(s(Ping(text='from the cache')), Ping).text)")
    env = dict(os.environ, LD_LIBRARY_PATH=os.pathsep.join(
        [str(venv / "lib"), os.environ.get("LD_LIBRARY_PATH", "")]))
    return subprocess.run([str(venv / "bin" / "python"), "-c", code], env=env, text=True,
                          capture_output=True, check=False)


@pytest.mark.slow
def test_a_second_venv_installs_from_the_cache_and_a_damaged_entry_is_built_again(
        tmp_path: Path, cache: Path, capsys: pytest.CaptureFixture[str]) -> None:
    bootstrap = load_bootstrap()
    source = demo_interface_package(tmp_path / "src")
    first = fresh_venv(tmp_path / "first")
    set_up(bootstrap, first, source)
    said = capsys.readouterr().out
    assert "building interface package demo_msgs" in said, said
    [entry] = entries(cache)
    assert entry.name.startswith("demo_msgs-") and (entry / "manifest.json").exists()

    second = fresh_venv(tmp_path / "second")
    set_up(bootstrap, second, source)
    said = capsys.readouterr().out
    assert "demo_msgs from the build cache (key" in said, said
    assert "building" not in said
    assert not (second / ".sar-build" / "demo_msgs").exists(), "cmake ran"
    assert bootstrap.Stamps(second).data.get("interface:demo_msgs")
    done = round_trip(second)
    assert done.stdout.strip() == "from the cache", done.stderr
    # The text files naming the prefix name this venv's.
    local_setup = (second / "share" / "demo_msgs" / "local_setup.sh").read_text()
    assert str(second) in local_setup and str(first) not in local_setup

    # A damaged entry (an installed module lost) is removed, built again and replaced.
    manifest = json.loads((entry / "manifest.json").read_text())
    [init] = [f for f in manifest["files"] if f.endswith("demo_msgs/msg/__init__.py")]
    (entry / "files" / init).unlink()
    third = fresh_venv(tmp_path / "third")
    set_up(bootstrap, third, source)
    said = capsys.readouterr().out
    assert f"entry {entry} does not install a working package: removed" in said, said
    assert "building interface package demo_msgs" in said, said
    assert [e.name for e in entries(cache)] == [entry.name]
    assert (entry / "files" / init).exists()
    assert round_trip(third).stdout.strip() == "from the cache"


def key_of(source: Path, env: dict[str, str], hook: Path,
           python: Path = Path(sys.executable)) -> str:
    return build_cache.build_key(source, python, env, options=["-DBUILD_TESTING=OFF"],
                                 inputs=[hook], exclude=["demo_msgs"])


def test_the_key_follows_what_the_build_reads_not_where_it_lies(tmp_path: Path) -> None:
    source = demo_interface_package(tmp_path / "src")
    hook = tmp_path / "hook.cmake"
    hook.write_text("# hook\n")
    ros = tmp_path / "ros"  # a ROS prefix: one rosidl package
    (ros / "share" / "rosidl_generator_c").mkdir(parents=True)
    (ros / "share" / "rosidl_generator_c" / "package.xml").write_text("<version>4.6.5</version>")
    env = dict(os.environ, CMAKE_PREFIX_PATH=str(ros))
    first = fresh_venv(tmp_path / "first") / "bin" / "python"
    key = key_of(source, env, hook, first)
    assert len(key) == 32 and key == key_of(source, env, hook, first)
    # The same ROS, package and interpreter at other paths (another clone and its venv, a
    # link farm): the same key.
    other = demo_interface_package(tmp_path / "clone")
    moved = tmp_path / "ros_elsewhere"
    ros.rename(moved)
    second = fresh_venv(tmp_path / "second") / "bin" / "python"
    assert key_of(other, dict(env, CMAKE_PREFIX_PATH=str(moved)), hook, second) == key
    env["CMAKE_PREFIX_PATH"] = str(moved)
    # Each input the installed files depend on changes it.
    (source / "msg" / "Ping.msg").write_text("string text\n")
    changed = key_of(source, env, hook)
    assert changed != key
    (source.parent / "sibling_msgs").mkdir()
    (source.parent / "sibling_msgs" / "package.xml").write_text("<package/>")
    assert key_of(source, env, hook) not in (key, changed)
    for change in (lambda: hook.write_text("# another hook\n"),
                   lambda: (moved / "share" / "rosidl_generator_c" / "package.xml").write_text(
                       "<version>4.6.6</version>")):
        before = key_of(source, env, hook)
        change()
        assert key_of(source, env, hook) != before
    # The package being built, where a prefix already holds it, is not ROS's identity.
    before = key_of(source, env, hook)
    (moved / "share" / "demo_msgs").mkdir()
    (moved / "share" / "demo_msgs" / "package.xml").write_text("<an old build/>")
    assert key_of(source, env, hook) == before


def test_an_interrupted_store_leaves_no_entry(tmp_path: Path,
                                              monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("SAR_INTERFACE_CACHE", str(tmp_path / "cache"))
    prefix = tmp_path / "prefix"
    installed = []
    for name in ("lib/liba.so", "share/a/package.xml", "share/a/local_setup.sh"):
        (prefix / name).parent.mkdir(parents=True, exist_ok=True)
        (prefix / name).write_text(f"{prefix}/{name}\n")
        installed.append(prefix / name)
    entry = build_cache.entry_path("a", "0" * 32)
    copied = []
    real_copy = build_cache.shutil.copy2

    def copy_then_fail(src, dst, **kwargs):
        if copied:
            raise OSError("disk full")
        copied.append(src)
        return real_copy(src, dst, **kwargs)

    monkeypatch.setattr(build_cache.shutil, "copy2", copy_then_fail)
    with pytest.raises(OSError, match="disk full"):
        build_cache.store(entry, installed, [str(prefix)])
    assert copied and not entry.exists()
    assert list((tmp_path / "cache").iterdir()) == [], "a partial entry was left"
    monkeypatch.setattr(build_cache.shutil, "copy2", real_copy)
    build_cache.store(entry, installed, [str(prefix)])
    # Restored at another prefix, its text names that prefix.
    elsewhere = tmp_path / "elsewhere"
    assert build_cache.restore(entry, [str(elsewhere)])
    assert (elsewhere / "share/a/local_setup.sh").read_text() == (
        f"{elsewhere}/share/a/local_setup.sh\n")
    # An entry missing its manifest (never written by store) is not used.
    (entry / "manifest.json").unlink()
    assert not build_cache.restore(entry, [str(tmp_path / "third")])


def test_only_the_entries_last_stored_or_used_are_kept(tmp_path: Path,
                                                       monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("SAR_INTERFACE_CACHE", str(tmp_path / "cache"))
    prefix = tmp_path / "prefix"
    (prefix / "share").mkdir(parents=True)
    (prefix / "share" / "f").write_text("f\n")
    stored = []
    for n in range(build_cache.KEEP + 2):
        stored.append(build_cache.entry_path("a", f"{n:032x}"))
        build_cache.store(stored[-1], [prefix / "share" / "f"], [str(prefix)])
        os.utime(stored[-1], (n, n))  # stored in this order
        if n == 0:
            assert build_cache.restore(stored[0], [str(tmp_path / "used")])  # used: kept
    other = build_cache.entry_path("a_b", "f" * 32)  # another package: never pruned with a
    build_cache.store(other, [prefix / "share" / "f"], [str(prefix)])
    kept = sorted(e.name for e in (tmp_path / "cache").iterdir())
    assert kept == sorted([other.name, stored[0].name,
                           *(e.name for e in stored[-(build_cache.KEEP - 1):])])
