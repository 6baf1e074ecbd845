"""The files a run was made of, kept in its recording: the tree, its includes, local plugins.

The recorder attaches every tree file the run read (the main file and, transitively, each
``include:``) and the source of every local plugin (``plugins:`` entries and
``--plugin-path`` entries that name a ``.py`` file or a folder; for a folder, each ``.py``
file in it). Each is an MCAP attachment named ``files/<path>``, its path relative to the
deepest folder holding them all, so the files keep their places beside each other and the
relative ``include:`` and ``plugins:`` entries resolve again once they are written out.
The metadata record names the main tree and the ``--plugin-path`` entries in that layout.

``sar-tree replay`` writes them out (:func:`extract`) and builds the tree from them alone.
Plugins named as installed modules are not copied: they are installed. Paths written
absolute inside the tree files still point where they pointed.
"""

from __future__ import annotations

import json
import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path, PurePosixPath

from sar_framework.engine.reading.tree_files import TreeFiles, normalise

PREFIX = "files/"
#: Metadata keys: the main tree's attachment, the ``--plugin-path`` entries (JSON list;
#: an attached entry starts with :data:`PREFIX`, a module name is kept as written).
TREE_KEY = "tree_attachment"
PLUGIN_PATHS_KEY = "plugin_paths"
MEDIA_TYPES = {".py": "text/x-python", ".yaml": "application/yaml", ".yml": "application/yaml"}


class SourcesError(ValueError):
    """A recording's attachments cannot be written out as files."""


@dataclass
class RunSources:
    """The files of a run, as they go into the recording.

    Attributes:
        attachments: Attachment name -> the file it holds.
        metadata: The metadata entries naming the main tree and the plugin paths.
    """

    attachments: dict[str, Path] = field(default_factory=dict)
    metadata: dict[str, str] = field(default_factory=dict)


def _plugin_files(path: Path) -> list[Path]:
    """The source files of a local plugin entry (none for a module name)."""
    if path.is_file():
        return [path]
    if path.is_dir():
        return sorted(p for p in path.glob("*.py") if p.is_file())
    return []


def _local(entry: str, base: Path) -> Path:
    path = Path(entry).expanduser()
    return normalise(path if path.is_absolute() else base / path)


def collect(tree: str, plugin_paths: Sequence[str] = (), cwd: Path | None = None) -> RunSources:
    """The tree files and local plugin sources of a run.

    Args:
        tree: The main tree file, as the run named it.
        plugin_paths: The run's ``--plugin-path`` entries (relative to ``cwd``).
        cwd: The run's working folder (default: this process's).

    Returns:
        The attachments (none when the tree file cannot be read) and their metadata.
    """
    base = Path.cwd() if cwd is None else cwd
    main = _local(tree, base)
    if not main.is_file():
        return RunSources()
    files = TreeFiles()
    files.visit(main, tree, ())
    paths = [p for p in files.files if p.is_file()]
    for entry, directory, _where in files.plugin_entries:
        paths.extend(_plugin_files(_local(entry, directory)))
    run_entries = [(entry, _local(entry, base)) for entry in plugin_paths if entry]
    for _entry, path in run_entries:
        paths.extend(_plugin_files(path))
    paths = list(dict.fromkeys(paths))
    root = Path(os.path.commonpath([p.parent for p in paths]))

    def name(path: Path) -> str:
        return PREFIX + path.relative_to(root).as_posix()

    entries = [name(path) if _plugin_files(path) else entry for entry, path in run_entries]
    return RunSources({name(p): p for p in paths},
                      {TREE_KEY: name(main), PLUGIN_PATHS_KEY: json.dumps(entries)})


def media_type(path: Path) -> str:
    """The attachment's media type, by the file's suffix."""
    return MEDIA_TYPES.get(path.suffix, "text/plain")


def _target(folder: Path, name: str) -> Path:
    relative = PurePosixPath(name[len(PREFIX):])
    if relative.is_absolute() or ".." in relative.parts:
        raise SourcesError(f"attachment '{name}' names a path outside the recording's files")
    return folder.joinpath(*relative.parts)


@dataclass
class ExtractedSources:
    """The run's files, written out.

    Attributes:
        tree: The main tree file, or None when the recording holds none.
        plugin_paths: The run's ``--plugin-path`` entries, pointing at the written files.
    """

    tree: Path | None
    plugin_paths: list[str]


def extract(attachments: Mapping[str, bytes], metadata: Mapping[str, str],
            folder: Path) -> ExtractedSources:
    """Write a recording's ``files/`` attachments into ``folder``, in their layout.

    Args:
        attachments: Attachment name -> bytes.
        metadata: The recorder's metadata record.
        folder: Where the files go (created).

    Returns:
        The main tree and the plugin paths, in ``folder``.

    Raises:
        SourcesError: An attachment names a path outside ``folder``, or the metadata
            is malformed.
    """
    for name, data in attachments.items():
        if name.startswith(PREFIX):
            target = _target(folder, name)
            target.parent.mkdir(parents=True, exist_ok=True)
            target.write_bytes(data)
    tree_name = metadata.get(TREE_KEY, "")
    tree = _target(folder, tree_name) if tree_name in attachments else None
    try:
        entries = json.loads(metadata.get(PLUGIN_PATHS_KEY) or "[]")
    except json.JSONDecodeError as err:
        raise SourcesError(f"metadata '{PLUGIN_PATHS_KEY}' is not JSON: {err}") from None
    if not isinstance(entries, list) or not all(isinstance(e, str) for e in entries):
        raise SourcesError(f"metadata '{PLUGIN_PATHS_KEY}' is not a list of paths")
    return ExtractedSources(tree, [str(_target(folder, e)) if e.startswith(PREFIX) else e
                                   for e in entries])
