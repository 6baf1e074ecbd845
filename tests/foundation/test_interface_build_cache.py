"""tools/build_cache.py: a venv's interface package comes from the build cache, not a build.

The builds here are real (a one-message package against this venv's rosidl), each venv a
fresh one that sees this venv's packages as a sourced ROS would; the cache is a folder of
this test's own (``SAR_INTERFACE_CACHE``), so nothing here hits the user's cache.
"""

from __future__ import annotations

import errno
import hashlib
import json
import os
import subprocess
import sys
import sysconfig
import venv as venv_module
from pathlib import Path

import pytest
from test_bootstrap import ROOT, demo_interface_package, load_interface_packages, load_module

PREFIX = Path(sys.prefix)
SITE = Path(sysconfig.get_paths()["purelib"])
sys.path.insert(0, str(ROOT / "tools"))  # build_cache imports setup_base as bootstrap does
build_cache = load_module(ROOT / "tools" / "build_cache.py")


def fresh_venv(path: Path, *, sees_this_venv: bool = True) -> Path:
    """A venv without pip; its interpreter also sees this venv's packages, unless told not."""
    venv_module.create(path, symlinks=True)
    if sees_this_venv:
        site = next((path / "lib").glob("python3*/site-packages"))
        (site / "this_venv.pth").write_text(f"import site; site.addsitedir({str(SITE)!r})\n")
    return path


def set_up(step, venv: Path, source: Path, sourced: bool = True) -> None:
    """Install ``source`` into ``venv`` as the set-up's interface step does."""
    ros = step.SourcedRos(prefix=str(PREFIX), python=sys.executable, version="3.11")
    step.build_interface_package(venv, source, step.Stamps(venv), ros if sourced else None)


def entries(cache: Path) -> list[Path]:
    return sorted(cache.iterdir()) if cache.exists() else []


def text_naming(prefix: Path, venv: Path, entry: Path) -> list[str]:
    """The files the entry installed into ``venv`` whose text names ``prefix``."""
    files = json.loads((entry / "manifest.json").read_text())["files"]
    return [f for f in files if str(prefix).encode() in (venv / f).read_bytes()]


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
def test_a_second_venv_installs_the_first_ones_build_from_the_cache(
        tmp_path: Path, cache: Path, capsys: pytest.CaptureFixture[str]) -> None:
    step = load_interface_packages()
    source = demo_interface_package(tmp_path / "src")
    first = fresh_venv(tmp_path / "first")
    set_up(step, first, source)
    said = capsys.readouterr().out
    assert "building interface package demo_msgs" in said, said
    [entry] = entries(cache)
    assert entry.name.startswith("demo_msgs-") and (entry / "manifest.json").exists()
    built_naming = text_naming(first, first, entry)
    assert any(f.endswith("local_setup.sh") for f in built_naming), built_naming

    second = fresh_venv(tmp_path / "second")
    set_up(step, second, source)
    said = capsys.readouterr().out
    assert "demo_msgs from the build cache (key" in said, said
    assert "building" not in said
    assert not (second / ".sar-build" / "demo_msgs").exists(), "cmake ran"
    assert step.Stamps(second).data.get("interface:demo_msgs")
    done = round_trip(second)
    assert done.stdout.strip() == "from the cache", done.stderr
    # Each file that named the first venv names this one instead.
    assert text_naming(first, second, entry) == []
    assert text_naming(second, second, entry) == built_naming


def fake_install(venv: Path, source: Path, builds: list[Path]) -> Path:
    """What a build of ``source`` installs, made up: a module naming the prefix, a script."""
    builds.append(venv)
    site = next((venv / "lib").glob("python3*/site-packages"))
    files = {site / source.name / "__init__.py": f"PREFIX = {str(venv)!r}\n",
             venv / "share" / source.name / "local_setup.sh": f"PREFIX={venv}\n"}
    for path, text in files.items():
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)
    manifest = venv / ".sar-build" / source.name / "install_manifest.txt"
    manifest.parent.mkdir(parents=True, exist_ok=True)
    manifest.write_text("".join(f"{path}\n" for path in files))
    return manifest


@pytest.fixture
def faked(tmp_path: Path, monkeypatch: pytest.MonkeyPatch):
    """The set-up's interface step with CMake's part made up (recorded in ``builds``)."""
    monkeypatch.setenv("SAR_INTERFACE_CACHE", str(tmp_path / "cache"))
    step = load_interface_packages()
    builds: list[Path] = []
    monkeypatch.setattr(step, "cmake_install",
                        lambda venv, source, env, options: fake_install(venv, source, builds))
    source = demo_interface_package(tmp_path / "src")

    def install(name: str) -> Path:
        venv = fresh_venv(tmp_path / name, sees_this_venv=False)
        set_up(step, venv, source, sourced=False)
        assert step.Stamps(venv).data.get("interface:demo_msgs"), "the step is not done"
        said = subprocess.run([str(venv / "bin" / "python"), "-c",
                               "import demo_msgs; print(demo_msgs.PREFIX)"],
                              capture_output=True, text=True, check=True).stdout
        assert said.strip() == str(venv), "the module does not name its venv"
        return venv

    return install, builds, tmp_path / "cache"


def escape(entry: Path, module: str) -> None:
    """Make the entry's manifest list ``module`` as ``../module``, its digest right."""
    content = b"PREFIX = 'outside'\n"
    (entry / module).parent.mkdir(parents=True, exist_ok=True)
    (entry / module).write_bytes(content)  # what files/../module names
    digest = hashlib.sha256(content).hexdigest()
    (entry / "manifest.json").write_text(json.dumps(
        {"prefixes": ["/nowhere"], "files": {f"../{module}": digest}}))


def test_a_damaged_or_unreadable_entry_is_removed_and_the_package_built_again(
        faked, capsys: pytest.CaptureFixture[str]) -> None:
    install, builds, cache = faked
    first = install("first")
    assert builds == [first]
    [entry] = entries(cache)
    second = install("second")
    assert builds == [first], "a build despite the entry"
    assert "demo_msgs from the build cache" in capsys.readouterr().out

    manifest = json.loads((entry / "manifest.json").read_text())
    [module] = [f for f in manifest["files"] if f.endswith("__init__.py")]
    damages = {"a changed file": lambda: (entry / "files" / module).write_text("PREFIX = 1\n"),
               "a lost file": (entry / "files" / module).unlink,
               "an unreadable manifest": lambda: (entry / "manifest.json").write_text("{"),
               "a manifest writing outside the prefix": lambda: escape(entry, module)}
    for n, (damage, make) in enumerate(damages.items()):
        make()
        venv = install(f"damaged{n}")
        said = capsys.readouterr().out
        assert f"entry {entry} does not install a working package: removed" in said, damage
        assert builds[-1] == venv, f"{damage}: not built again"
        assert entries(cache) == [entry], damage
        assert build_cache.restore(entry, [str(second)]), f"{damage}: not replaced"
    assert len(builds) == 1 + len(damages)
    assert not (second.parent / module).exists(), "a file was written outside the venv"


def test_a_cache_that_cannot_be_written_never_fails_the_set_up(
        faked, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]) -> None:
    install, builds, cache = faked
    cache.write_text("a file where the cache folder should be\n")
    first = install("first")
    assert builds == [first]
    assert "could not keep demo_msgs-" in capsys.readouterr().out
    cache.unlink()

    # A full disk: the entry is not kept, and no partial one is left.
    def disk_full(*args, **kwargs):
        raise OSError(errno.ENOSPC, "No space left on device")

    real_copy = build_cache.shutil.copy2
    monkeypatch.setattr(build_cache.shutil, "copy2", disk_full)
    second = install("second")
    assert builds == [first, second]
    assert "No space left on device" in capsys.readouterr().out
    assert entries(cache) == []
    monkeypatch.setattr(build_cache.shutil, "copy2", real_copy)

    # A read-only cache (root ignores modes, so refused where the code writes): its entries
    # are still used, and a damaged one neither removed nor in the way of a build.
    install("third")
    [entry] = entries(cache)
    real_utime, real_mkdtemp = os.utime, build_cache.tempfile.mkdtemp

    def refused(path) -> None:
        if Path(path).is_relative_to(cache):
            raise OSError(errno.EROFS, "Read-only file system", str(path))

    def utime(path, *args, **kwargs) -> None:
        refused(path)
        real_utime(path, *args, **kwargs)

    def mkdtemp(*args, dir, **kwargs) -> str:
        refused(dir)
        return real_mkdtemp(*args, dir=dir, **kwargs)

    monkeypatch.setattr(build_cache.os, "utime", utime)
    monkeypatch.setattr(build_cache.tempfile, "mkdtemp", mkdtemp)
    count = len(builds)
    install("fourth")
    assert len(builds) == count, "a build despite the entry"
    (entry / "files" / next(iter(json.loads((entry / "manifest.json").read_text())["files"]))
     ).write_text("damaged\n")
    fifth = install("fifth")
    assert builds[-1] == fifth
    said = capsys.readouterr().out
    assert f"entry {entry} does not install a working package: could not remove it" in said
    assert "could not keep" in said

    # A cache this user may not even look into (root may, so refused where the code looks).
    real_exists = Path.exists

    def exists(path: Path) -> bool:
        if path.is_relative_to(cache):
            raise PermissionError(errno.EACCES, "Permission denied", str(path))
        return real_exists(path)

    monkeypatch.setattr(Path, "exists", exists)
    sixth = install("sixth")
    assert builds[-1] == sixth
    assert "could not read the build cache ([Errno 13] Permission denied" in (
        capsys.readouterr().out)


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
    # A package whose manifest cannot be read still gives a key (the build says what is wrong).
    (moved / "share" / "broken" / "package.xml").mkdir(parents=True)
    assert key_of(source, env, hook) != before


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


def test_restored_text_names_the_new_prefixes_where_it_named_the_old_ones(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("SAR_INTERFACE_CACHE", str(tmp_path / "cache"))
    built = tmp_path / "p" / ".venv"
    ros = tmp_path / "ros" / "jazzy" / "a longer prefix"
    text = f'PREFIX="{built}"\n{built}/share/a;{built}-compat/bin\n{ros}/lib:{built}\n'
    binary = b"\0\x7fELF" + f"{built}/lib".encode()
    (built / "share").mkdir(parents=True)
    (built / "share" / "text").write_text(text)
    (built / "share" / "binary").write_bytes(binary)
    entry = build_cache.entry_path("a", "0" * 32)
    build_cache.store(entry, [built / "share" / "text", built / "share" / "binary"],
                      [str(built), str(ros)])
    # The new ROS prefix holds the old venv's path: one pass never rewrites it again.
    here, ros_here = tmp_path / "q" / "venv", f"{built}/ros"
    assert build_cache.restore(entry, [str(here), ros_here])
    assert (here / "share" / "text").read_text() == (
        f'PREFIX="{here}"\n{here}/share/a;{built}-compat/bin\n{ros_here}/lib:{here}\n')
    assert (here / "share" / "binary").read_bytes() == binary
    # Other prefixes than the build's: only the install prefix is known to move.
    elsewhere = tmp_path / "elsewhere"
    assert build_cache.restore(entry, [str(elsewhere)])
    assert (elsewhere / "share" / "text").read_text() == text.replace(
        f'"{built}"', f'"{elsewhere}"').replace(f"{built}/", f"{elsewhere}/").replace(
        f":{built}\n", f":{elsewhere}\n")


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
