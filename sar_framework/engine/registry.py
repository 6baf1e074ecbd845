"""Plugin discovery: built-ins, installed entry points and local modules or dirs.

Three sources feed one :class:`Registry`:

* built-ins: every module of the ``sar_plugins`` package (``plugins/``);
* installed packages: the entry-point group ``sar_framework.plugins``; an entry
  point names a module (or package) to scan, or one plugin class;
* local paths: a ``.py`` file, a directory of ``.py`` files or a dotted module
  name, given with ``--plugin-path`` or in a tree's ``plugins:`` key.

Only a class whose own ``__dict__`` holds the :func:`~.plugin.leaf` mark (or, for a
control or decorator kind, :func:`~.kind_plugin.node_kind`'s) is a plugin (a subclass
of a plugin is not silently the same plugin). A module that fails to import becomes a
diagnostic naming it and the exception, never a traceback; two plugins with one name is
an error naming both sources.
"""

from __future__ import annotations

import dataclasses
import importlib
import importlib.metadata
import importlib.util
import pkgutil
import threading
from collections.abc import Iterable, Iterator, Sequence
from pathlib import Path
from types import ModuleType
from typing import Any

from sar_framework.engine.diagnostics import Diagnostic, SourceLocation, display_path
from sar_framework.engine.kind_plugin import KIND_ATTRIBUTE, KindSpec
from sar_framework.engine.nodes.kind_model import NodeKind
from sar_framework.engine.nodes.node_kinds import RESERVED_KINDS
from sar_framework.engine.plugin import PLUGIN_ATTRIBUTE, PluginSpec, constructor_problems
from sar_framework.engine.plugin_import import (
    class_location,
    exception_text,
    exec_file,
    failure_location,
    fallback_location,
    is_module_name,
    module_file,
    same_definition,
)

#: The entry-point group third-party packages register plugins under.
ENTRY_POINT_GROUP = "sar_framework.plugins"
#: The import name of the built-in plugin package.
BUILTIN_PACKAGE = "sar_plugins"
_lock = threading.RLock()
# Local plugin files already imported: resolved path -> module or the import failure.
_path_modules: dict[Path, ModuleType | BaseException] = {}
# The shared built-in + entry-point registry, discovered once per process.
_default: dict[str, Registry] = {}


def _marked(cls: type) -> bool:
    """Whether ``cls`` itself (not a base class) is marked as a plugin."""
    return PLUGIN_ATTRIBUTE in cls.__dict__ or KIND_ATTRIBUTE in cls.__dict__


class Registry:
    """The known leaf plugins, by name, plus the problems met while finding them.

    Attributes:
        diagnostics: Import failures, duplicate names and bad declarations.
    """

    def __init__(self) -> None:
        self._plugins: dict[str, PluginSpec] = {}
        self._kinds: dict[str, KindSpec] = {}
        self.diagnostics: list[Diagnostic] = []

    def copy(self) -> Registry:
        """Return an independent copy (to extend with a tree's local plugins)."""
        other = Registry()
        other._plugins = dict(self._plugins)
        other._kinds = dict(self._kinds)
        other.diagnostics = list(self.diagnostics)
        return other

    def get(self, name: str) -> PluginSpec | None:
        """Return the plugin called ``name``, or None."""
        return self._plugins.get(name)

    def __contains__(self, name: object) -> bool:
        return name in self._plugins

    def __iter__(self) -> Iterator[PluginSpec]:
        """Iterate over the plugins, sorted by name."""
        return iter(sorted(self._plugins.values(), key=lambda p: p.name))

    def __len__(self) -> int:
        return len(self._plugins)

    def names(self) -> list[str]:
        """Return the plugin names, sorted."""
        return sorted(self._plugins)

    def kind_plugin(self, name: str) -> KindSpec | None:
        """Return the control or decorator plugin called ``name``, or None."""
        return self._kinds.get(name)

    def kind(self, name: str) -> NodeKind | None:
        """Return the declaration of the plugin's control or decorator ``name``, or None."""
        spec = self._kinds.get(name)
        return spec.kind if spec is not None else None

    def kind_plugins(self) -> list[KindSpec]:
        """Return the control and decorator plugins, sorted by name."""
        return [self._kinds[name] for name in sorted(self._kinds)]

    def add(self, cls: type, source: str, location: SourceLocation | None = None) -> None:
        """Register one plugin class.

        Args:
            cls: A class marked with :func:`~.plugin.leaf` or :func:`~.kind_plugin.node_kind`.
            source: Where it came from, for messages and ``sar-tree plugins``.
            location: Where to report a problem when the class's source is unknown.
        """
        import py_trees  # only once a plugin module, which imported it, gave a class

        spec: PluginSpec | KindSpec = (cls.__dict__.get(PLUGIN_ATTRIBUTE)
                                       or cls.__dict__[KIND_ATTRIBUTE])
        known = self._plugins.get(spec.name) or self._kinds.get(spec.name)
        if known is not None and same_definition(known.cls, cls):
            return  # one definition reached twice (re-export, package and path)
        if not issubclass(cls, py_trees.behaviour.Behaviour):
            problem = f"plugin '{spec.name}' is not a py_trees behaviour (from {source})"
        elif spec.name in RESERVED_KINDS:
            problem = f"plugin name '{spec.name}' is reserved (from {source})"
        elif known is not None:
            problem = f"plugin '{spec.name}' is defined twice: in {known.source} and in {source}"
        elif isinstance(spec, KindSpec):
            self._kinds[spec.name] = dataclasses.replace(spec, source=source)
            return
        else:
            self._plugins[spec.name] = dataclasses.replace(spec, source=source)
            for problem in constructor_problems(spec):  # a warning: such plugins still work
                where = class_location(cls) or fallback_location(location, source)
                self.diagnostics.append(Diagnostic(where, f"plugin '{spec.name}': {problem}",
                                                   severity="warning"))
            return
        # Finding the class's line reads its file: only for a problem to report.
        where = class_location(cls) or fallback_location(location, source)
        self.diagnostics.append(Diagnostic(where, problem))

    def add_module(self, module: ModuleType, source: str | None = None) -> int:
        """Register every plugin class defined in (or re-exported by) a module.

        Args:
            module: An imported module.
            source: The source to record; defaults to the module name and file.

        Returns:
            How many plugin classes the module holds.
        """
        if source is None:
            file = getattr(module, "__file__", None)
            source = f"{module.__name__} ({display_path(file)})" if file else module.__name__
        count = 0
        for value in list(vars(module).values()):
            if isinstance(value, type) and _marked(value):
                self.add(value, source)
                count += 1
        return count

    def import_module(
        self, name: str, *, location: SourceLocation | None = None, submodules: bool = True
    ) -> bool:
        """Import a module by name (and, for a package, its modules) and register its plugins.

        Args:
            name: A dotted module name.
            location: Where to report a failure when it has no better place.
            submodules: Whether to import every module of a package.

        Returns:
            True when the module imported.
        """
        module = self._import(name, location)
        if module is None:
            return False
        self.add_module(module)
        path = getattr(module, "__path__", None)
        if submodules and path is not None:
            for info in sorted(pkgutil.iter_modules(path), key=lambda i: i.name):
                sub = self._import(f"{name}.{info.name}", location)
                if sub is not None:
                    self.add_module(sub)
        return True

    def _import(self, name: str, location: SourceLocation | None) -> ModuleType | None:
        try:
            return importlib.import_module(name)
        except KeyboardInterrupt:
            raise
        except BaseException as exc:  # SystemExit too: a plugin must not end the process
            file = None
            try:
                found = importlib.util.find_spec(name)
                file = found.origin if found is not None else None
            except (ImportError, ValueError, AttributeError):
                pass
            fallback = fallback_location(location, display_path(file) if file else name)
            self.diagnostics.append(
                Diagnostic(
                    failure_location(exc, file, fallback) if location is None else location,
                    f"cannot import plugin module '{name}': {exception_text(exc)}",
                )
            )
            return None

    def import_file(self, path: Path, *, location: SourceLocation | None = None) -> bool:
        """Import one ``.py`` file as a standalone module and register its plugins.

        Args:
            path: The file.
            location: Where to report a failure (e.g. the tree's ``plugins:`` entry);
                by default, the failing line of the file.

        Returns:
            True when the file imported.
        """
        resolved = path.resolve()
        shown = display_path(path)
        with _lock:
            module = _path_modules.get(resolved)
            if module is None:
                module = exec_file(resolved)
                _path_modules[resolved] = module
        if isinstance(module, BaseException):
            fallback = fallback_location(None, shown)
            here = failure_location(module, str(resolved), fallback)
            message = f"cannot import plugin file '{shown}': {exception_text(module)}"
            if location is not None:
                message += f" (at {here})"
                here = location
            self.diagnostics.append(Diagnostic(here, message))
            return False
        self.add_module(module, shown)
        return True

    def import_path(
        self, entry: str, base: Path, *, location: SourceLocation | None = None
    ) -> None:
        """Import a plugin path: a ``.py`` file, a directory of them, or a module name.

        Args:
            entry: As written (relative paths are relative to ``base``).
            base: The directory relative paths start from.
            location: Where the entry was written, for diagnostics.
        """
        path = Path(entry).expanduser()
        if not path.is_absolute():
            path = base / path
        if path.is_dir():
            files = sorted(p for p in path.glob("*.py") if not p.name.startswith("_"))
            for file in files:
                self.import_file(file, location=location)
            if not files:
                self.diagnostics.append(
                    Diagnostic(
                        fallback_location(location, display_path(path)),
                        f"plugin directory '{entry}' holds no .py files",
                    )
                )
            return
        if path.is_file():
            self.import_file(path, location=location)
            return
        if entry.endswith(".py") or "/" in entry or "\\" in entry or not is_module_name(entry):
            self.diagnostics.append(
                Diagnostic(fallback_location(location, entry),
                           f"plugin path '{entry}' does not exist")
            )
            return
        self.import_module(entry, location=location)

    def import_entry_points(self) -> None:
        """Register the plugins of every installed ``sar_framework.plugins`` entry point."""
        try:
            points = importlib.metadata.entry_points(group=ENTRY_POINT_GROUP)
        except Exception as exc:  # broken metadata of some installed distribution
            self.diagnostics.append(
                Diagnostic(
                    SourceLocation(f"<entry points {ENTRY_POINT_GROUP}>", 1, 1),
                    f"cannot list entry points: {exception_text(exc)}",
                )
            )
            return
        for point in sorted(points, key=lambda p: p.name):
            dist = getattr(point, "dist", None)
            label = f"entry point '{point.name} = {point.value}'"
            if dist is not None:
                label += f" ({dist.metadata['Name']})"
            here = SourceLocation(f"<{label}>", 1, 1)
            if point.attr:
                try:
                    obj: Any = point.load()
                except Exception as exc:
                    self.diagnostics.append(
                        Diagnostic(
                            failure_location(exc, module_file(point.module), here),
                            f"cannot load {label}: {exception_text(exc)}",
                        )
                    )
                    continue
                if isinstance(obj, type) and _marked(obj):
                    self.add(obj, label, here)
                else:
                    self.diagnostics.append(
                        Diagnostic(here, f"{label} does not name a plugin class or module")
                    )
            else:
                self.import_module(point.value, location=None)

    def check_declarations(self) -> None:
        """Report reference params naming plugins that are not registered."""
        for spec in self._plugins.values():
            for param in spec.params:
                if param.ref is not None and param.ref not in self._plugins:
                    where = class_location(spec.cls) or SourceLocation(spec.source, 1, 1)
                    self.diagnostics.append(
                        Diagnostic(
                            where,
                            f"param '{param.name}' of plugin '{spec.name}' refers to unknown "
                            f"plugin '{param.ref}'",
                        )
                    )


def discover(
    plugin_paths: Sequence[str | Path] = (),
    *,
    builtins: bool = True,
    entry_points: bool = True,
    base: Path | None = None,
) -> Registry:
    """Build a registry from scratch.

    Args:
        plugin_paths: Extra ``.py`` files, directories or module names.
        builtins: Whether to import the built-in ``sar_plugins`` package.
        entry_points: Whether to load installed ``sar_framework.plugins`` entry points.
        base: The directory relative ``plugin_paths`` start from (default: cwd).

    Returns:
        The registry; problems are in its ``diagnostics``.
    """
    registry = Registry()
    if builtins:
        registry.import_module(BUILTIN_PACKAGE)
    if entry_points:
        registry.import_entry_points()
    extend(registry, plugin_paths, base=base)
    return registry


def extend(
    registry: Registry, plugin_paths: Iterable[str | Path], *, base: Path | None = None
) -> Registry:
    """Import extra plugin paths into ``registry`` (in place) and check declarations.

    Args:
        registry: The registry to extend.
        plugin_paths: ``.py`` files, directories or module names.
        base: The directory relative paths start from (default: cwd).

    Returns:
        ``registry``.
    """
    start = base if base is not None else Path.cwd()
    for entry in plugin_paths:
        registry.import_path(str(entry), start)
    registry.check_declarations()
    return registry


def core_registry() -> Registry:
    """Return a new registry of the built-ins alone: no installed plugins, so no app's leaves.

    What the core's committed schema and palette (``sar_framework/schema/``) describe; an
    app's own are this registry extended with the app's leaf package.
    """
    return discover(entry_points=False)


def default_registry(*, refresh: bool = False) -> Registry:
    """Return the built-in + entry-point registry, discovered once per process.

    Args:
        refresh: Discover again (after installing a package, in tests).

    Returns:
        The shared registry; copy it before extending it.
    """
    with _lock:
        registry = _default.get("registry")
        if registry is None or refresh:
            registry = _default["registry"] = discover()
        return registry
