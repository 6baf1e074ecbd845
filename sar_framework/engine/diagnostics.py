"""Diagnostics: what the engine says about a tree file, GCC style.

Every problem the engine finds in a tree file becomes a :class:`Diagnostic`
that names the file, line and column (both 1-based) and a message::

    trees/mission.yaml:12:9: error: unknown plugin 'NavigateToPos' (did you mean 'NavigateToPose'?)

Problems are collected in one pass; :class:`TreeLoadError` carries all of them
at once so a user fixes a file in one go instead of one error per run.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path


@dataclass(frozen=True, order=True)
class SourceLocation:
    """A position in a source file.

    Attributes:
        file: The file, as the user named it (kept relative when it was given relative).
        line: 1-based line number.
        col: 1-based column number.
    """

    file: str
    line: int
    col: int

    def __str__(self) -> str:
        return f"{self.file}:{self.line}:{self.col}"


@dataclass(frozen=True)
class Diagnostic:
    """One problem found in a tree file.

    Attributes:
        location: Where the problem is.
        message: What is wrong, in words a user can act on.
        severity: ``"error"`` or ``"warning"``.
    """

    location: SourceLocation
    message: str
    severity: str = "error"

    def __str__(self) -> str:
        return f"{self.location}: {self.severity}: {self.message}"


class TreeLoadError(Exception):
    """Raised when a tree file cannot be loaded; carries every diagnostic found.

    Args:
        diagnostics: The problems, in the order they were found.
    """

    def __init__(self, diagnostics: Sequence[Diagnostic]) -> None:
        self.diagnostics: list[Diagnostic] = sorted(
            diagnostics, key=lambda d: (d.location.file, d.location.line, d.location.col)
        )
        super().__init__("\n".join(str(d) for d in self.diagnostics))


def display_path(path: Path | str) -> str:
    """Return ``path`` relative to the working directory when it lies below it.

    Args:
        path: A file path.

    Returns:
        The path to print in a diagnostic.
    """
    p = Path(path)
    try:
        return str(p.resolve().relative_to(Path.cwd().resolve()))
    except ValueError:
        return str(p)


def did_you_mean(word: str, candidates: Iterable[str]) -> str:
    """Suggest the closest candidate to a misspelt word.

    Args:
        word: What the user wrote.
        candidates: What would have been valid.

    Returns:
        ``" (did you mean 'X'?)"`` or an empty string when nothing is close.
    """
    import difflib  # only when a name is unknown

    close = difflib.get_close_matches(word, list(candidates), n=1, cutoff=0.6)
    return f" (did you mean '{close[0]}'?)" if close else ""
