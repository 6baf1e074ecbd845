"""Repeated console lines, collapsed with a count (``sar-tree run``'s progress).

A tree can take the same decision on every tick: a reactive tree whose first goal is
blocked alternates that goal and its fallback, and each goal is told once. Shown as it
comes, that is a line a tick. :class:`RepeatCollapser` shows a line once while it keeps
coming back among the last few lines shown, and says how often it came back when
something new is said (or at the end)::

    goal (0.00, 0.00) sent to navigate_to_pose
    goal (3.00, 3.00) sent to navigate_to_pose
    (repeated: 'goal (0.00, 0.00) sent to navigate_to_pose' 312 more times;
     'goal (3.00, 3.00) sent to navigate_to_pose' 311 more times)
"""

from __future__ import annotations

import re
from collections import deque

#: How many of the last distinct lines shown a repeat may come back from.
RECENT_LINES = 8
NUMBER = re.compile(r"\d+(?:\.\d+)?")


class RepeatCollapser:
    """Decides which lines to show; counts the ones it holds back.

    Args:
        window: How many recent distinct lines a repeat is looked for among.
    """

    def __init__(self, window: int = RECENT_LINES) -> None:
        self._recent: deque[str] = deque(maxlen=window)
        self._held: dict[str, int] = {}
        self._first: dict[str, str] = {}  # key -> the text shown for it

    def lines(self, text: str, key: str | None = None) -> list[str]:
        """The lines to show now for ``text``: none when it repeats a recent line.

        Args:
            text: The line that came.
            key: What makes two lines "the same" (default: the text itself).

        Returns:
            The count of what was held back, if anything, then ``text``; or nothing.
        """
        key = text if key is None else key
        if key in self._recent:
            shown = self._first.setdefault(key, text)
            self._held[shown] = self._held.get(shown, 0) + 1
            return []
        out = self.flush()
        self._recent.append(key)
        self._first[key] = text
        return [*out, text]

    def flush(self) -> list[str]:
        """The count line of what was held back (empty when nothing was); forget it."""
        if not self._held:
            return []
        counts = "; ".join(f"{text!r} {count} more time{'s' if count > 1 else ''}"
                           for text, count in self._held.items())
        self._held = {}
        self._first = {key: text for key, text in self._first.items() if key in self._recent}
        return [f"(repeated: {counts})"]


def numbers_as_one(text: str) -> str:
    """``Goal 9 aborted after 0.9 s`` and ``Goal 11 aborted after 0.6 s`` as one key.

    For a process's own log lines, whose counters and timings differ on every repeat.
    """
    return NUMBER.sub("#", text)
