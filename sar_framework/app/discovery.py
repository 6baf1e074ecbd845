"""Which apps there are, and which a tree uses.

Apps come from the entry-point group ``sar_framework.apps`` (an entry point names an
:class:`~.app.App` object), like installed plugins, and from the modules of the tree's own
plugins (the tree's ``plugins:`` key, ``--plugin-path``): a module, or its package, that
defines ``APP``. A tree uses an app when one of its leaves needs a context object the app
provides.
"""

from __future__ import annotations

import importlib.metadata
import sys
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

from sar_framework.app.app import App

if TYPE_CHECKING:
    from sar_framework.engine.registry import Registry
    from sar_framework.engine.spec import TreeSpec

ENTRY_POINT_GROUP = "sar_framework.apps"
"""The entry-point group packages register apps under."""
MODULE_ATTRIBUTE = "APP"
"""The name a plugin module (or its package) gives its app."""
_installed: list[App] = []


class AppError(ValueError):
    """An app that cannot be used (it fails to load, or two provide one context object)."""


def discover_apps(*, refresh: bool = False) -> list[App]:
    """The installed apps (entry points), loaded once per process.

    Raises:
        AppError: An entry point that fails to load or is not an :class:`App`.
    """
    if _installed and not refresh:
        return list(_installed)
    found: list[App] = []
    for point in importlib.metadata.entry_points(group=ENTRY_POINT_GROUP):
        try:
            app = point.load()
        except Exception as err:
            raise AppError(f"app entry point {point.name!r} ({point.value}): "
                           f"{type(err).__name__}: {err}") from None
        if not isinstance(app, App):
            raise AppError(f"app entry point {point.name!r} ({point.value}) is not an App")
        found.append(app)
    _installed[:] = found
    return list(found)


def installed_apps() -> list[App]:
    """The installed apps, or [] when one fails to load.

    For what lists them without running a tree (the command line's options, the parameter
    docs); a run's checks call :func:`discover_apps` and report the failure.
    """
    try:
        return discover_apps()
    except AppError:
        return []


def apps_status_text(document: Mapping[str, Any],
                     apps: Sequence[App] | None = None) -> list[str]:
    """The apps' words about a tree status document (:attr:`App.status_text`).

    Args:
        document: A tree status document.
        apps: The apps that speak (the installed ones when None).
    """
    return [app.status_text(document) for app in (installed_apps() if apps is None else apps)
            if app.status_text]


def with_installed(used: Iterable[App]) -> list[App]:
    """The installed apps, then those of ``used`` not among them (a view's apps)."""
    apps = installed_apps()
    known = {app.name for app in apps}
    return apps + [app for app in used if app.name not in known]


def view_apps(tree: str | Path | None, plugin_paths: Sequence[str | Path] = ()) -> list[App]:
    """The apps a view of a run of ``tree`` speaks with: the installed ones, then the tree's.

    The tree's own apps come from its ``plugins:`` (and ``plugin_paths``), as a replay finds
    them in the recorded files; a tree that is missing, does not validate or whose apps do
    not load adds none (its run says why).

    Args:
        tree: The tree file, or None when it is not known.
        plugin_paths: Extra plugin files, directories or modules.
    """
    if not tree or not Path(tree).is_file():
        return installed_apps()
    try:
        return with_installed(tree_apps(tree, plugin_paths))
    except AppError:
        return installed_apps()


def _module_apps(modules: Iterable[str]) -> list[App]:
    """The apps the given modules, or their packages, define as ``APP``."""
    apps: list[App] = []
    for name in modules:
        parts = name.split(".")
        for end in range(len(parts), 0, -1):
            app = getattr(sys.modules.get(".".join(parts[:end])), MODULE_ATTRIBUTE, None)
            if isinstance(app, App) and app not in apps:
                apps.append(app)
    return apps


def apps_for(spec: TreeSpec, registry: Registry) -> list[App]:
    """The apps ``spec`` uses: those providing a context object one of its leaves needs.

    Args:
        spec: A validated tree.
        registry: The plugins it was validated against (with its local ones).

    Returns:
        The apps, in discovery order (installed ones first).

    Raises:
        AppError: Two apps provide one context object the tree needs.
    """
    needed: set[str] = set()
    modules: list[str] = []
    for node in spec.nodes():
        plugin = registry.get(node.kind)
        if plugin is not None:
            needed.update(plugin.context)
            modules.append(plugin.cls.__module__)
    candidates = discover_apps()
    candidates += [a for a in _module_apps(modules)
                   if a.name not in {c.name for c in candidates}]
    used = [app for app in candidates if needed & set(app.provides)]
    for key in sorted(needed):
        names = [app.name for app in used if key in app.provides]
        if len(names) > 1:
            raise AppError(f"context object {key!r} is provided by more than one app: "
                           + ", ".join(names))
    return used


def tree_apps(tree: str | Path, plugin_paths: Sequence[str | Path] = ()) -> list[App]:
    """The apps the tree file ``tree`` uses ([] when it does not validate: loading says why).

    Args:
        tree: A tree file.
        plugin_paths: Extra plugin files, directories or modules.

    Raises:
        AppError: An app fails to load, or two provide one context object.
    """
    from sar_framework.engine.api import validate

    result = validate(tree, plugin_paths=plugin_paths)
    return [] if result.spec is None else apps_for(result.spec, result.registry)
