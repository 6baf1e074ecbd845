"""The one error a script raises: what is wrong and where, inside the script's own text."""

from __future__ import annotations


class ScriptError(Exception):
    """A script that cannot be parsed, does not type-check, or failed while running.

    Args:
        message: What is wrong, in words a tree author can act on.
        column: 1-based column of the culprit in its line of the script.
        line: 1-based line of the culprit in the script (1 for one-line scripts).
        script: The script's text, when known (named in ``str(error)``).

    Attributes:
        message: As given.
        column: As given.
        line: As given.
        script: As given.
    """

    def __init__(self, message: str, column: int, line: int = 1, script: str | None = None) -> None:
        self.message = message
        self.column = column
        self.line = line
        self.script = script
        super().__init__(str(self))

    def __str__(self) -> str:
        where = f"column {self.column}"
        if self.line != 1:
            where = f"line {self.line}, {where}"
        text = f"{self.message} ({where})"
        if self.script is not None:
            text += f" in script {self.script!r}"
        return text

    def in_script(self, script: str) -> ScriptError:
        """Return this error naming ``script`` (itself when it already names one)."""
        if self.script is not None:
            return self
        return ScriptError(self.message, self.column, self.line, script)
