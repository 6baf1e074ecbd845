"""Repeated console lines, collapsed with a count (``sar-tree run``'s progress).

A tree can take the same decision on every tick: the reference tree with a blocked zone
alternates its zone goal and its base goal (the course's design), and each goal says
"Returning to base with 3 zone(s) unvisited." once. Shown as it comes, that is a line a
tick. :class:`RepeatCollapser` shows a line once while it keeps coming back among the
last few lines shown, and says how often it came back when something new is said (or at
the end)::

    Returning to base with 3 zone(s) unvisited.
    --- Zone 2/4: zone_b (3.00, 3.00) ---
    (repeated: 'Returning to base with 3 zone(s) unvisited.' 312 more times;
     '--- Zone 2/4: zone_b (3.00, 3.00) ---' 311 more times)
"""

from __future__ import annotations

from collections import deque

#: How many of the last distinct lines shown a repeat may come back from.
RECENT_LINES = 4


class RepeatCollapser:
    """Decides which lines to show; counts the ones it holds back.

    Args:
        window: How many recent distinct lines a repeat is looked for among.
    """

    def __init__(self, window: int = RECENT_LINES) -> None:
        self._recent: deque[str] = deque(maxlen=window)
        self._held: dict[str, int] = {}

    def lines(self, text: str) -> list[str]:
        """The lines to show now for ``text``: none when it repeats a recent line.

        Args:
            text: The line that came.

        Returns:
            The count of what was held back, if anything, then ``text``; or nothing.
        """
        if text in self._recent:
            self._held[text] = self._held.get(text, 0) + 1
            return []
        out = self.flush()
        self._recent.append(text)
        return [*out, text]

    def flush(self) -> list[str]:
        """The count line of what was held back (empty when nothing was); forget it."""
        if not self._held:
            return []
        counts = "; ".join(f"{text!r} {count} more time{'s' if count > 1 else ''}"
                           for text, count in self._held.items())
        self._held = {}
        return [f"(repeated: {counts})"]
