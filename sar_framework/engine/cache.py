"""A content-keyed cache of validated trees: skip read + validate when nothing changed.

A clean validation (no diagnostics at all) of content validated clean once before stores
the :class:`~.spec.TreeSpec` (the first one only leaves a small marker: a file edited
between runs, as in an edit-and-run loop, never pays for storing its tree) under a key
made of:

* the engine: this cache's format, the spec version, the engine's own source files
  (content), PyYAML's version and the Python version;
* the tree file's absolute path and a digest of its bytes;
* the registry's :meth:`~.registry.Registry.fingerprint` (before and after the tree's
  local plugins are added) and the caller's extra plugin paths;
* every included file's absolute path and a digest of its bytes.

A load looks the key up, re-hashing the main file and every recorded include, rebuilds
the registry with the tree's local plugins, and only when every part matches (and the
registry reports no problem) skips straight to the spec. Anything else is a miss and
takes the full path, so diagnostics are always those of a full validation; a file with
diagnostics is never stored.

Two layers share one entry format: an in-process LRU (:data:`MEMORY_ENTRIES`) and a
per-user directory, ``$SAR_TREE_CACHE_DIR``, else ``$XDG_CACHE_HOME/sar_framework/trees``,
else ``~/.cache/sar_framework/trees``. Entries are pickles written by this module only,
atomically (temporary file + rename), into a directory created private (0700); an entry
not owned by the current user, unreadable, truncated, corrupt or from another version is
a miss. No cache problem ever becomes an error: the cache only makes a load faster.

File names in a spec are kept as absolute paths in an entry and turned back into
display names (relative to the current directory, or as the caller named the main file)
on every hit, so a hit from another directory or through another relative path prints
the same locations as a full validation.

``SAR_TREE_CACHE=0`` (or ``off``, ``false``, ``no``) disables both layers.
"""

from __future__ import annotations

import contextlib
import hashlib
import importlib
import os
import pickle
import sys
import tempfile
import threading
from collections import OrderedDict
from collections.abc import Sequence
from pathlib import Path
from typing import Any, NamedTuple

import yaml

from sar_framework.engine import validate as validation
from sar_framework.engine.diagnostics import display_path
from sar_framework.engine.registry import Registry, default_registry
from sar_framework.engine.spec import Category, NodeSpec, TreeSpec
from sar_framework.engine.yaml_source import new_location

#: Version of the entry format; bump when the stored layout changes.
CACHE_FORMAT = 2
#: Version of the TreeSpec model as stored (py_trees-independent).
SPEC_VERSION = 1
#: Entries kept in memory, most recently used first out last.
MEMORY_ENTRIES = 32
#: Entries kept on disk; the oldest are removed beyond this.
DISK_ENTRIES = 256
#: Environment variable that disables the cache when set to 0/off/false/no.
ENV_SWITCH = "SAR_TREE_CACHE"
#: Environment variable naming the cache directory (overrides the XDG default).
ENV_DIR = "SAR_TREE_CACHE_DIR"

_MAGIC = b"SARTREE\0"
_HEADER = _MAGIC + CACHE_FORMAT.to_bytes(2, "big")
_SUFFIX = ".tree"
_OFF = {"0", "off", "false", "no"}
_CATEGORIES = tuple(Category)
_CATEGORY_INDEX = {c: i for i, c in enumerate(_CATEGORIES)}

# The modules whose code decides what a tree file means.
_ENGINE_MODULES = ("validate", "yaml_source", "quick_validate", "quick_yaml", "node_kinds",
                   "spec", "diagnostics", "plugin", "registry", "cache")

_lock = threading.Lock()
_memory: OrderedDict[str, _Entry] = OrderedDict()
_engine_stamp: list[str] = []


class _Entry(NamedTuple):
    """One cached tree: what must still match, and the spec in its stored form.

    Stored on disk as a plain tuple (no class reference), rebuilt with ``_Entry(*state)``.
    """

    key: str  # digest of the engine, the main file's path and content, the registry
    includes: tuple[tuple[str, str], ...]  # (absolute path, content digest), other files
    plugin_entries: tuple[tuple[str, str], ...]  # (entry, directory) of plugins: keys
    registry: str  # fingerprint of the registry with the tree's local plugins
    files: tuple[str, ...]  # absolute paths, indexed by the stored locations
    spec: bytes  # pickle of the flat spec (see _encode); empty in a marker (seen once)


def enabled(requested: bool = True) -> bool:
    """Return whether a load should use the cache.

    Args:
        requested: What the caller asked for (``cache=`` / ``--no-cache``).

    Returns:
        False when the caller or ``SAR_TREE_CACHE`` turned it off.
    """
    return requested and os.environ.get(ENV_SWITCH, "1").strip().lower() not in _OFF


def directory() -> Path:
    """Return the on-disk cache directory (it may not exist yet)."""
    explicit = os.environ.get(ENV_DIR)
    if explicit:
        return Path(explicit)
    xdg = os.environ.get("XDG_CACHE_HOME", "")
    base = Path(xdg) if os.path.isabs(xdg) else Path.home() / ".cache"
    return base / "sar_framework" / "trees"


def clear_memory() -> None:
    """Forget the in-process entries (the disk store stays)."""
    with _lock:
        _memory.clear()


def _digest(data: bytes) -> str:
    return hashlib.blake2b(data, digest_size=20).hexdigest()


def _engine() -> str:
    """Digest of what the engine is: versions and its own validating source files."""
    if not _engine_stamp:
        from sar_framework import __version__

        digest = hashlib.blake2b(digest_size=20)
        digest.update(repr((CACHE_FORMAT, SPEC_VERSION, validation.FORMAT_VERSION, __version__,
                            yaml.__version__, sys.implementation.cache_tag)).encode())
        for name in _ENGINE_MODULES:
            module = importlib.import_module(f"sar_framework.engine.{name}")
            try:
                digest.update(Path(module.__file__ or "").read_bytes())
            except OSError:
                digest.update(f"unreadable {module.__name__}".encode())
        _engine_stamp.append(digest.hexdigest())
    return _engine_stamp[0]


def _slot(main: Path, base_fingerprint: str, plugin_paths: Sequence[str | Path]) -> str:
    """Name of the one entry a main file has (its content is checked inside)."""
    extra = [str(p) for p in plugin_paths]
    where = os.getcwd() if extra else ""  # relative plugin paths start from the cwd
    text = repr((_engine(), str(main), base_fingerprint, extra, where))
    return _digest(text.encode("utf-8", "surrogateescape"))


def _key(slot: str, content: str) -> str:
    return _digest(f"{slot}\0{content}".encode())


# -- the stored form of a spec --------------------------------------------------------------
# Nodes in depth-first order, each a flat tuple holding its location; children by count,
# references by index; file names become indexes into the entry's list of absolute paths.
def _encode(spec: TreeSpec, file_index: dict[str, int]) -> bytes | None:
    """Flatten a spec; None when a location names a file outside the load."""
    rows: list[tuple[Any, ...]] = []
    append = rows.append
    node_index: dict[int, int] = {}
    with_refs: list[NodeSpec] = []
    category_index = _CATEGORY_INDEX
    stack = [spec.root]
    pop = stack.pop
    while stack:
        node = pop()
        node_index[id(node)] = len(rows)
        loc = node.location
        file = file_index.get(loc.file)
        if file is None:
            return None
        children = node.children
        append((node.kind, category_index[node.category], node.name, node.uid, file, loc.line,
                loc.col, node.attrs, len(children), node.id, node.subtree))
        if children:
            stack.extend(reversed(children))
        if node.refs:
            with_refs.append(node)
    refs = [(node_index[id(n)], [(k, node_index[id(t)]) for k, t in n.refs.items()])
            for n in with_refs]
    head = (spec.name, spec.description, spec.format, spec.plugin_paths)
    return pickle.dumps((head, rows, refs), protocol=pickle.HIGHEST_PROTOCOL)


def _decode(data: bytes, files: list[str], source: str) -> TreeSpec:
    """Rebuild a spec (new objects every time), naming files as ``files`` says."""
    head, rows, refs = pickle.loads(data)  # our own entry (see _read_disk)
    # Instances are made the way unpickling makes them (no __init__, a filled __dict__):
    # ordinary objects, in a fraction of the time of the dataclass constructors.
    new = object.__new__
    nodes: list[NodeSpec] = []
    open_lists: list[list[Any]] = []  # [children list, how many still to come]
    categories = _CATEGORIES
    for kind, category, name, uid, file, line, col, attrs, count, ident, subtree in rows:
        node = new(NodeSpec)
        children: list[NodeSpec] = []
        node.__dict__ = {
            "kind": kind, "category": categories[category], "name": name, "uid": uid,
            "location": new_location(files[file], line, col), "attrs": attrs,
            "children": children, "id": ident, "refs": {}, "subtree": subtree,
        }
        nodes.append(node)
        if open_lists:
            parent = open_lists[-1]
            parent[0].append(node)
            parent[1] -= 1
            if not parent[1]:
                open_lists.pop()
        if count:
            open_lists.append([children, count])
    for at, pairs in refs:
        node_refs = nodes[at].refs
        for name, target in pairs:
            node_refs[name] = nodes[target]
    name, description, fmt, plugin_paths = head
    return TreeSpec(name, description, nodes[0], source, fmt, plugin_paths)


# -- the disk layer -------------------------------------------------------------------------
def _read_disk(slot: str) -> _Entry | None:
    path = directory() / (slot + _SUFFIX)
    try:
        with path.open("rb") as stream:
            if hasattr(os, "getuid") and os.fstat(stream.fileno()).st_uid != os.getuid():
                return None  # only ever unpickle what this user wrote
            data = stream.read()
    except OSError:
        return None
    if not data.startswith(_HEADER):
        return None
    try:
        state = pickle.loads(data[len(_HEADER):])  # written by us, owned by this user
        entry = _Entry(*state)
    except Exception:  # truncated, corrupt or foreign: a miss
        return None
    return entry if isinstance(entry.key, str) and isinstance(entry.spec, bytes) else None


def _write_disk(slot: str, entry: _Entry) -> None:
    folder = directory()
    folder.mkdir(mode=0o700, parents=True, exist_ok=True)
    data = _HEADER + pickle.dumps(tuple(entry), protocol=pickle.HIGHEST_PROTOCOL)
    handle, temporary = tempfile.mkstemp(dir=folder, prefix=".tmp-", suffix=_SUFFIX)
    try:
        with os.fdopen(handle, "wb") as stream:
            stream.write(data)
        os.replace(temporary, folder / (slot + _SUFFIX))
    except BaseException:
        Path(temporary).unlink(missing_ok=True)
        raise
    _prune(folder)


def _prune(folder: Path) -> None:
    """Keep the newest :data:`DISK_ENTRIES` entries."""
    entries = [e for e in os.scandir(folder) if e.name.endswith(_SUFFIX)]
    if len(entries) <= DISK_ENTRIES:
        return
    entries.sort(key=lambda e: e.stat().st_mtime_ns)
    for old in entries[: len(entries) - DISK_ENTRIES]:
        Path(old.path).unlink(missing_ok=True)


# -- lookup and store -----------------------------------------------------------------------
def _file_digest(path: str | Path) -> str | None:
    try:
        with open(path, "rb") as stream:
            return _digest(stream.read(validation.yaml_source.MAX_FILE_BYTES + 1))
    except OSError:
        return None


def _lookup(
    path: str | Path, main: Path, base: Registry, plugin_paths: Sequence[str | Path]
) -> validation.ValidationResult | None:
    if base.diagnostics:
        return None  # a full validation reports them
    content = _file_digest(main)
    if content is None:
        return None
    base_fingerprint = base.fingerprint()
    slot = _slot(main, base_fingerprint, plugin_paths)
    with _lock:
        entry = _memory.get(slot)
        if entry is not None:
            _memory.move_to_end(slot)
    if entry is None:
        entry = _read_disk(slot)
        if entry is None:
            return None
        _remember(slot, entry)
    if entry.key != _key(slot, content) or not entry.spec:
        return None  # another content, or a marker: this content was only seen once
    if any(_file_digest(file) != digest for file, digest in entry.includes):
        return None
    entries = [(e, Path(d), None) for e, d in entry.plugin_entries]
    registry = validation.local_registry(base, plugin_paths, entries)
    fingerprint = base_fingerprint if registry is base else registry.fingerprint()
    if registry.diagnostics or fingerprint != entry.registry:
        return None
    shown = str(path)
    names = [shown if file == str(main) else display_path(file) for file in entry.files]
    spec = _decode(entry.spec, names, shown)
    return validation.ValidationResult(spec, [], [], registry, None,
                                       dict(zip(map(Path, entry.files), names, strict=True)),
                                       [(e, Path(d)) for e, d in entry.plugin_entries])


def _remember(slot: str, entry: _Entry) -> None:
    with _lock:
        _memory[slot] = entry
        _memory.move_to_end(slot)
        while len(_memory) > MEMORY_ENTRIES:
            _memory.popitem(last=False)


def _store(
    main: Path,
    base: Registry,
    plugin_paths: Sequence[str | Path],
    result: validation.ValidationResult,
    digests: dict[Path, str],
) -> None:
    spec = result.spec
    if spec is None or result.diagnostics or base.diagnostics or main not in digests:
        return
    files = [str(p) for p in result.files]
    by_name = {name: i for i, name in enumerate(result.files.values())}
    if len(by_name) != len(files) or set(digests) != set(result.files):
        return  # two files shown alike, or a file read that the result does not name
    base_fingerprint = base.fingerprint()
    slot = _slot(main, base_fingerprint, plugin_paths)
    key = _key(slot, digests[main])
    with _lock:
        previous = _memory.get(slot)  # (a lookup has just put any disk entry here)
    if previous is None or previous.key != key:
        # Seen once: leave a marker and store on the second clean validation of this
        # content, so a file edited between runs never pays for encoding its tree.
        entry = _Entry(key, (), (), "", (), b"")
    else:
        data = _encode(spec, by_name)
        if data is None:
            return
        includes = tuple((str(p), d) for p, d in digests.items() if p != main)
        fingerprint = (base_fingerprint if result.registry is base
                       else result.registry.fingerprint())
        entry = _Entry(key, includes, tuple((e, str(d)) for e, d in result.plugin_entries),
                       fingerprint, tuple(files), data)
    _remember(slot, entry)
    with contextlib.suppress(OSError):  # read-only or full: memory still helps this process
        _write_disk(slot, entry)


def validate(
    path: str | Path,
    *,
    registry: Registry | None = None,
    plugin_paths: Sequence[str | Path] = (),
    cache: bool = True,
) -> validation.ValidationResult:
    """Validate a tree file, through the cache when enabled.

    Args:
        path: The tree file, as the user named it.
        registry: The plugins to check against; default: built-ins and entry points.
        plugin_paths: Extra plugin files, dirs or modules.
        cache: Whether to use the cache (``SAR_TREE_CACHE=0`` turns it off anyway).

    Returns:
        What :func:`~.validate.validate_file` returns for the same file.
    """
    if not enabled(cache):
        return validation.validate_file(path, registry=registry, plugin_paths=plugin_paths)
    base = registry if registry is not None else default_registry()
    main = validation.main_file(path)
    try:
        hit = _lookup(path, main, base, plugin_paths)
    except Exception:  # a cache problem is never the caller's problem
        hit = None
    if hit is not None:
        return hit
    digests: dict[Path, str] = {}

    def record(file: Path, data: bytes) -> None:
        digests[file] = _digest(data)

    result = validation.validate_file(path, registry=base, plugin_paths=plugin_paths,
                                      on_read=record)
    with contextlib.suppress(Exception):  # never the caller's problem either
        _store(main, base, plugin_paths, result, digests)
    return result
