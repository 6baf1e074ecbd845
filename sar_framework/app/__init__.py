"""Apps: what one kind of mission adds to the mission-neutral core.

An :class:`~.app.App` provides a mission's context objects, its parameters and their
checks, the processes it needs beside the runner, its event kinds and its parts of the
report. A tree uses an app when one of its leaves needs a context object the app provides
(:func:`~.discovery.apps_for`); a tree that uses none runs on the core alone.
"""

from sar_framework.app.app import App, AppOption, AppProcess, AppRun, ServiceCall
from sar_framework.app.discovery import (
    ENTRY_POINT_GROUP,
    AppError,
    apps_for,
    discover_apps,
    installed_apps,
    tree_apps,
)

__all__ = ["ENTRY_POINT_GROUP", "App", "AppError", "AppOption", "AppProcess", "AppRun",
           "ServiceCall", "apps_for", "discover_apps", "installed_apps", "tree_apps"]
