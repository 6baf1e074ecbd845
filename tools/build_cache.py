"""A per-user cache of built interface packages, addressed by the content of their inputs.

Every fresh venv (a new clone's ``make setup``, the sourced-ROS test's venv) would configure,
generate and link each interface package again, even with every compile a ccache hit. After
a build, the files CMake installed (its ``install_manifest.txt``) are stored relative to the
install prefix in ``<cache>/<package>-<key>/``; a later build with the same key copies them
into its prefix instead. The key is a digest of everything the installed files depend on:
the package's folder and its siblings (a package may use its siblings' types), the
interpreter and its installed distributions, the compilers, CMake, the build options and
hook, and the ROS packages found on ``CMAKE_PREFIX_PATH`` by content (their ``package.xml``
files), never by path, so another clone or another prefix holding the same ROS hits.

The installed tree is relocatable: the libraries carry no RPATH (ROS's loader finds them on
the library path the venv's start-up sets), the generated Python has no paths, and the few
text files naming a build-time prefix (``local_setup.sh``, the Python generator's CMake
export naming NumPy's headers in the venv, the ament index's ``parent_prefix_path`` marker
over a sourced ROS) are rewritten to the current prefixes when copied (see :func:`relocate`).

An entry is written in a temporary folder and renamed into place, so a concurrent or
interrupted run never leaves a half entry; its manifest holds each file's digest, so a
damaged entry is found while it is copied. Cache folder: ``$SAR_INTERFACE_CACHE``, else
``$XDG_CACHE_HOME/sar_framework/interfaces``, else ``~/.cache/sar_framework/interfaces``.
Standard library only: this runs before any venv exists.
"""

from __future__ import annotations

import contextlib
import functools
import hashlib
import json
import os
import re
import shutil
import subprocess
import tempfile
from collections.abc import Callable, Iterable, Sequence
from pathlib import Path

from setup_base import cache_home, files_under, log
from sourced_ros import normalised

CACHE_ENV = "SAR_INTERFACE_CACHE"
MANIFEST = "manifest.json"  # written last: an entry without one is never used
FILES = "files"
KEEP = 8  # entries kept per package (about 2 MB each): the newest

_PYTHON_IDENTITY = (
    "import sys, sysconfig, importlib.metadata as m\n"
    "print(sys.version); print(sysconfig.get_config_var('SOABI'))\n"
    "print(sysconfig.get_paths()['include'])\n"
    "print(*sorted({f\"{d.metadata['Name']}=={d.version}\" for d in m.distributions()}),"
    " sep='\\n')\n"
)


def cache_root() -> Path:
    """The folder holding the cache's entries."""
    return Path(os.environ.get(CACHE_ENV) or cache_home() / "interfaces")


def _sha256(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def tree_digest(folder: Path) -> str:
    """Digest of every file below ``folder``: names relative to it, and contents."""
    h = hashlib.sha256()
    for path in sorted(files_under(folder)):
        h.update(f"{path.relative_to(folder).as_posix()}\0{_sha256(path)}\0".encode())
    return h.hexdigest()


@functools.cache
def _tool_versions(python: str, pythonpath: str, compilers: tuple[str, ...]) -> str:
    """The interpreter (version, ABI, distributions), compilers' and CMake's versions."""
    env = dict(os.environ, PYTHONPATH=pythonpath)
    lines = []
    # A tool that does not answer still gives a key: the build then says what is wrong.
    for label, cmd in (("python", [python, "-c", _PYTHON_IDENTITY]),  # never its path
                       *((tool, [tool, "--version"]) for tool in (*compilers, "cmake"))):
        try:
            done = subprocess.run(cmd, env=env, capture_output=True, text=True, check=False)
        except OSError as err:
            lines.append(f"{label}: {type(err).__name__}")
            continue
        answer = done.stdout if label == "python" else (done.stdout.splitlines() or [""])[0]
        lines.append(f"{label}: {answer}")
    return "\n".join(lines)


def ros_identity(prefixes: Sequence[str], exclude: Iterable[str]) -> str:
    """Digest of the ``package.xml`` of every package the build can find, by content.

    Args:
        prefixes: The prefixes CMake searches, first first (a name found twice is the first).
        exclude: Package names left out (the ones being built, which a prefix may hold).
    """
    found: dict[str, Path] = {}
    for prefix in prefixes:
        for manifest in sorted(Path(prefix).glob("share/*/package.xml")):
            found.setdefault(manifest.parent.name, manifest)
    h = hashlib.sha256()
    for name in sorted(set(found) - set(exclude)):
        try:
            content = _sha256(found[name])
        except OSError as err:  # a dangling or unreadable manifest: the build will say
            content = type(err).__name__
        h.update(f"{name}\0{content}\0".encode())
    return h.hexdigest()


def build_key(source: Path, python: Path, env: dict[str, str], *, options: Sequence[str],
              inputs: Sequence[Path], exclude: Iterable[str]) -> str:
    """The cache key of building ``source`` with ``python`` in ``env``.

    Args:
        source: The package's folder (its siblings are digested too).
        python: The interpreter the build generates Python code for.
        env: The build's environment (``CMAKE_PREFIX_PATH``, ``CC``, ``CXX``, ``PYTHONPATH``).
        options: The CMake options that are not paths.
        inputs: Files the build reads besides the package (the CMake project include).
        exclude: Package names not to count as the ROS the build finds (ours).
    """
    compilers = (env.get("CC", "cc"), env.get("CXX", "c++"))
    prefixes = [p for p in env.get("CMAKE_PREFIX_PATH", "").split(os.pathsep) if p]
    exclude = set(exclude)
    # Our packages' own distributions (rosidl installs one per package) come and go.
    ours = tuple(f"{normalised(name)}==" for name in exclude)
    tools = _tool_versions(str(python), env.get("PYTHONPATH", ""), compilers).splitlines()
    parts = [tree_digest(source.parent), source.name,
             *(line for line in tools if not normalised(line).startswith(ours)),
             ros_identity(prefixes, exclude), *options, *map(_sha256, inputs)]
    return hashlib.sha256("\0".join(parts).encode()).hexdigest()[:32]


def entry_path(package: str, key: str) -> Path:
    """Where the entry of ``package`` built with ``key`` lives."""
    return cache_root() / f"{package}-{key}"


def store(entry: Path, installed: Iterable[Path], prefixes: Sequence[str]) -> None:
    """Store installed files as ``entry``, atomically; an existing entry is kept.

    Args:
        entry: The entry's folder (see :func:`entry_path`).
        installed: The absolute paths the install wrote, all below ``prefixes[0]``.
        prefixes: The install prefix, then the other prefixes the build searched.
    """
    entry.parent.mkdir(parents=True, exist_ok=True)
    scratch = Path(tempfile.mkdtemp(prefix=f".{entry.name}.", dir=entry.parent))
    try:
        files = {}
        for path in installed:
            relative = path.relative_to(prefixes[0]).as_posix()
            (scratch / FILES / relative).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(path, scratch / FILES / relative, follow_symlinks=False)
            files[relative] = _sha256(scratch / FILES / relative)
        (scratch / MANIFEST).write_text(json.dumps({"prefixes": list(prefixes),
                                                    "files": files}, indent=1))
        try:
            scratch.rename(entry)
        except OSError:
            if not (entry / MANIFEST).exists():  # lost to a concurrent run's entry: fine
                raise
    finally:
        shutil.rmtree(scratch, ignore_errors=True)
    with contextlib.suppress(OSError):  # another run may be pruning too
        prune(entry)


def prune(entry: Path, keep: int = KEEP) -> None:
    """Remove all but the ``keep`` entries of ``entry``'s package last stored or used."""
    package = entry.name.rsplit("-", 1)[0]
    others = sorted(entry.parent.glob(f"{package}-*"), key=lambda e: e.stat().st_mtime)
    for old in [e for e in others if e.name.rsplit("-", 1)[0] == package][:-keep]:
        discard(old)


def relocate(data: bytes, moves: dict[str, str]) -> bytes:
    """``data`` with each old prefix (a key of ``moves``) replaced by its new one.

    A prefix is replaced only where it names that folder or a path below it, never where a
    longer name merely starts with it (``/a/.venv`` in ``/a/.venv-compat``); all in one pass,
    so a new prefix holding an old one is never rewritten twice. The longest prefix wins.
    """
    olds = sorted((old.encode() for old in moves), key=len, reverse=True)
    if not olds:
        return data
    new = {old.encode(): value.encode() for old, value in moves.items()}
    pattern = re.compile(b"(" + b"|".join(map(re.escape, olds)) + rb")(?![\w.+\-\x80-\xff])")
    return pattern.sub(lambda match: new[match.group(1)], data)


def _moves(old: Sequence[str], new: Sequence[str]) -> dict[str, str]:
    """Build-time prefix to current prefix: the n-th to the n-th when there are as many."""
    pairs = zip(old, new, strict=True) if len(old) == len(new) else [(old[0], new[0])]
    moves = {a.rstrip("/"): b.rstrip("/") for a, b in pairs}
    return {a: b for a, b in moves.items() if a and a != b}  # never "/" itself


def _inside(relative: str) -> bool:
    """Whether a manifest's file name stays below the prefix (no absolute name, no ``..``)."""
    path = Path(relative)
    return not path.is_absolute() and ".." not in path.parts


def restore(entry: Path, prefixes: Sequence[str]) -> bool:
    """Copy an entry's files into ``prefixes[0]``; False when it is missing or damaged.

    Text files naming the build's prefixes name the current ones instead (the n-th prefix
    becomes the n-th one here, when there are as many).

    Args:
        entry: The entry's folder.
        prefixes: The install prefix, then the other prefixes the build searches.
    """
    try:
        manifest = json.loads((entry / MANIFEST).read_text())
        files: dict[str, str] = manifest["files"]
        moves = _moves(manifest["prefixes"], prefixes)
        if not all(map(_inside, files)):
            return False
        for relative, sha in files.items():
            stored = entry / FILES / relative
            if _sha256(stored) != sha:
                return False
            target = Path(prefixes[0]) / relative
            target.parent.mkdir(parents=True, exist_ok=True)
            target.unlink(missing_ok=True)
            data = stored.read_bytes()
            text = b"\0" not in data and not stored.is_symlink()
            moved = relocate(data, moves) if text else data
            if moved != data:
                target.write_bytes(moved)
                shutil.copymode(stored, target)
            else:
                shutil.copy2(stored, target, follow_symlinks=False)
    except (OSError, ValueError, KeyError, TypeError, AttributeError, IndexError):
        return False
    with contextlib.suppress(OSError):  # a cache this user may not write is still used
        os.utime(entry)  # used: the last entry pruned
    return True


def install_entry(entry: Path, prefixes: Sequence[str], works: Callable[[], bool]) -> bool:
    """Install an entry's files, if there is one; whether they work.

    An entry whose files are damaged or do not work is removed (and said so).

    Args:
        entry: The entry's folder.
        prefixes: The install prefix, then the other prefixes the build searches.
        works: Checks the installed package (e.g. that it imports).
    """
    try:
        if not entry.exists():
            return False
    except OSError as err:  # the cache only saves time: build instead
        log(f"could not read the build cache ({err}); building")
        return False
    if restore(entry, prefixes) and works():
        return True
    outcome = "removed" if discard(entry) else "could not remove it"
    log(f"the build cache's entry {entry} does not install a working package: {outcome}")
    return False


def keep(entry: Path, install_manifest: Path, prefixes: Sequence[str]) -> None:
    """Store what CMake's ``install_manifest.txt`` lists as ``entry``; never fail for it.

    Args:
        entry: The entry's folder.
        install_manifest: The build's list of installed files (absolute paths).
        prefixes: The install prefix, then the other prefixes the build searched.
    """
    try:
        installed = install_manifest.read_text().splitlines()
        store(entry, [Path(line) for line in installed if line], prefixes)
    except (OSError, ValueError) as err:  # the cache only saves time (ValueError: a file
        # installed outside the prefix)
        log(f"could not keep {entry.name} in the build cache ({err})")


def discard(entry: Path) -> bool:
    """Remove an entry (renamed away first, so no run copies from a half-removed one).

    Never fails: an entry that cannot be removed (a cache this user may not write) stays,
    and a later run finds it damaged again and builds. Returns whether it is gone.
    """
    try:
        doomed = Path(tempfile.mkdtemp(prefix=f".{entry.name}.", dir=entry.parent))
    except OSError:
        return False
    with contextlib.suppress(OSError):  # another run removed or replaced it meanwhile
        entry.rename(doomed / "entry")
    shutil.rmtree(doomed, ignore_errors=True)
    return not entry.exists()
