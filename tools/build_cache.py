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
text files naming a build-time prefix (``local_setup.sh``, a CMake export, the ament index's
``parent_prefix_path`` marker) are rewritten to the current prefixes when copied.

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
        h.update(f"{name}\0{_sha256(found[name])}\0".encode())
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
        old = manifest["prefixes"]
        same_shape = len(old) == len(prefixes)
        pairs = zip(old, prefixes, strict=True) if same_shape else [(old[0], prefixes[0])]
        moves = sorted(((a.encode(), b.encode()) for a, b in pairs if a != b),
                       key=lambda pair: -len(pair[0]))
        for relative, sha in files.items():
            stored = entry / FILES / relative
            if _sha256(stored) != sha:
                return False
            target = Path(prefixes[0]) / relative
            target.parent.mkdir(parents=True, exist_ok=True)
            target.unlink(missing_ok=True)
            data = stored.read_bytes()
            if moves and b"\0" not in data and any(a in data for a, _ in moves):
                for a, b in moves:
                    data = data.replace(a, b)
                target.write_bytes(data)
                shutil.copymode(stored, target)
            else:
                shutil.copy2(stored, target, follow_symlinks=False)
        os.utime(entry)  # used: the last entry pruned
    except (OSError, ValueError, KeyError, TypeError):
        return False
    return True


def install_entry(entry: Path, prefixes: Sequence[str], works: Callable[[], bool]) -> bool:
    """Install an entry's files, if there is one; whether they work.

    An entry whose files are damaged or do not work is removed (and said so).

    Args:
        entry: The entry's folder.
        prefixes: The install prefix, then the other prefixes the build searches.
        works: Checks the installed package (e.g. that it imports).
    """
    if not entry.exists():
        return False
    if restore(entry, prefixes) and works():
        return True
    log(f"the build cache's entry {entry} does not install a working package: removed")
    discard(entry)
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
    except OSError as err:  # the cache only saves time
        log(f"could not keep {entry.name} in the build cache ({err})")


def discard(entry: Path) -> None:
    """Remove an entry (renamed away first, so no run copies from a half-removed one)."""
    if not entry.exists():
        return
    doomed = Path(tempfile.mkdtemp(prefix=f".{entry.name}.", dir=entry.parent))
    with contextlib.suppress(OSError):  # another run removed or replaced it meanwhile
        entry.rename(doomed / "entry")
    shutil.rmtree(doomed, ignore_errors=True)
