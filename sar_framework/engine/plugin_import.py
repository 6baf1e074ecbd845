"""How plugin code is imported, and where its failures are reported.

Helpers of :mod:`.registry`: a local ``.py`` file is imported under a private module
name; an import failure is located at the failing line of the plugin's own file when
there is one; two classes are one plugin when they are one definition.
"""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path
from types import ModuleType

from sar_framework.engine.diagnostics import SourceLocation, display_path

#: Package name under which local plugin files are imported.
LOCAL_PREFIX = "sar_local_plugins"


def fallback_location(location: SourceLocation | None, file: str) -> SourceLocation:
    """Return ``location``, or the start of ``file`` when there is none."""
    return location if location is not None else SourceLocation(file, 1, 1)


def failure_location(
    exc: BaseException, file: str | None, fallback: SourceLocation
) -> SourceLocation:
    """Point at the line of ``file`` that raised, or at ``fallback``."""
    if isinstance(exc, SyntaxError) and exc.filename and exc.lineno:
        return SourceLocation(display_path(exc.filename), exc.lineno, max(exc.offset or 1, 1))
    if file:
        import traceback  # only when a plugin failed

        target = str(Path(file).resolve())
        for frame in reversed(traceback.extract_tb(exc.__traceback__)):
            if frame.filename and str(Path(frame.filename).resolve()) == target and frame.lineno:
                return SourceLocation(display_path(file), frame.lineno, 1)
    return fallback


def exception_text(exc: BaseException) -> str:
    """Return ``Type: first line of the message`` (a SyntaxError's without its location)."""
    text = (exc.msg if isinstance(exc, SyntaxError) else str(exc)).strip().splitlines()
    first = text[0] if text else ""
    return f"{type(exc).__name__}: {first}" if first else type(exc).__name__


def class_location(cls: type) -> SourceLocation | None:
    """Return where a class is defined, or None when its source is unknown."""
    import inspect  # only when a plugin class is registered

    try:
        file = inspect.getsourcefile(cls)
        line = inspect.getsourcelines(cls)[1]
    except (OSError, TypeError):
        return None
    return SourceLocation(display_path(file), line, 1) if file else None


def same_definition(first: type, second: type) -> bool:
    """Whether two classes are one definition.

    They are when they are the same class, or the same class statement of one file
    imported twice (as an installed package and by path).

    Args:
        first: A plugin class.
        second: Another plugin class.

    Returns:
        True when they are one plugin.
    """
    if first is second:
        return True
    files = [getattr(sys.modules.get(c.__module__), "__file__", None) for c in (first, second)]
    return (
        None not in files
        and first.__qualname__ == second.__qualname__
        and Path(files[0]).resolve() == Path(files[1]).resolve()  # type: ignore[arg-type]
    )


def module_file(name: str) -> str | None:
    """Return the file a module name would import from, or None."""
    try:
        found = importlib.util.find_spec(name)
    except (ImportError, ValueError, AttributeError):
        return None
    return found.origin if found is not None else None


def is_module_name(text: str) -> bool:
    """Whether ``text`` is a dotted module name."""
    return all(part.isidentifier() for part in text.split("."))


def exec_file(path: Path) -> ModuleType | BaseException:
    """Import ``path`` under a unique private module name; return it or the failure."""
    import hashlib  # only for local plugin files

    digest = hashlib.sha1(str(path).encode()).hexdigest()[:10]
    stem = "".join(c if c.isalnum() else "_" for c in path.stem)
    name = f"{LOCAL_PREFIX}.{stem}_{digest}"
    spec = importlib.util.spec_from_file_location(name, path)
    if spec is None or spec.loader is None:
        return ImportError(f"not a Python module: {path}")
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    try:
        spec.loader.exec_module(module)
    except (KeyboardInterrupt, GeneratorExit):
        sys.modules.pop(name, None)
        raise
    except BaseException as exc:  # SystemExit too: a plugin must not end the process
        sys.modules.pop(name, None)
        return exc
    return module
