"""A clock for tests: seconds that move only when the test moves them."""

from __future__ import annotations

from types import SimpleNamespace


class ManualClock:
    """Callable as a clock (``CLOCK_KEY``, a recorder's clock); returns ``now``.

    Args:
        start: The first reading, in seconds.
    """

    def __init__(self, start: float = 0.0) -> None:
        self.now = start

    def __call__(self) -> float:
        return self.now

    def node(self) -> SimpleNamespace:
        """A stand-in for an rclpy node on this clock: ``get_clock().now().nanoseconds``."""
        clock = SimpleNamespace(now=lambda: SimpleNamespace(nanoseconds=int(self.now * 1e9)))
        return SimpleNamespace(get_clock=lambda: clock)
