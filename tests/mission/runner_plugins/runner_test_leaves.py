"""Leaves for the runner's tests: predictable, tick-counting, no Nav2 needed."""

from __future__ import annotations

import time
from typing import Any

import py_trees
from py_trees.common import Status

from sar_framework.engine.plugin import Param, leaf


@leaf(
    params=[
        Param("ticks", int, default=3, minimum=0, description="RUNNING for this many ticks."),
        Param("succeed", bool, default=True, description="Then SUCCESS (true) or FAILURE."),
        Param("message", str, default="", description="feedback_message at the end."),
    ],
    context=["zone_manager"],
)
class Countdown(py_trees.behaviour.Behaviour):
    """RUNNING for ``ticks`` ticks, then SUCCESS or FAILURE with ``message``."""

    def __init__(self, name: str, *, ticks: int, succeed: bool, message: str,
                 zone_manager: Any) -> None:
        super().__init__(name=name)
        self._ticks = ticks
        self._succeed = succeed
        self._message = message
        self._zones = zone_manager.total_zones()
        self._left = ticks

    def initialise(self) -> None:
        """Start counting again."""
        self._left = self._ticks

    def update(self) -> Status:
        """Count down; then the verdict."""
        if self._left > 0:
            self._left -= 1
            self.feedback_message = f"{self._left} ticks left"
            return Status.RUNNING
        default = f"done after {self._ticks} ticks ({self._zones} zones)"
        self.feedback_message = self._message or default
        return Status.SUCCESS if self._succeed else Status.FAILURE


@leaf(params=[Param("seconds", float, default=5.0, minimum=0.0,
                    description="How long setup() blocks.")])
class SlowSetup(py_trees.behaviour.Behaviour):
    """Blocks in ``setup()`` (to exercise the runner's setup timeout)."""

    def __init__(self, name: str, *, seconds: float) -> None:
        super().__init__(name=name)
        self._seconds = seconds

    def setup(self, **kwargs: Any) -> None:
        """Sleep."""
        time.sleep(self._seconds)

    def update(self) -> Status:
        """Succeed."""
        return Status.SUCCESS


@leaf()
class Forever(py_trees.behaviour.Behaviour):
    """RUNNING forever; logs through the node when it is terminated."""

    def __init__(self, name: str) -> None:
        super().__init__(name=name)
        self._node: Any = None

    def setup(self, **kwargs: Any) -> None:
        """Keep the node for logging."""
        self._node = kwargs["node"]

    def update(self) -> Status:
        """Never finish."""
        return Status.RUNNING

    def terminate(self, new_status: Status) -> None:
        """Say so when stopped while running."""
        if new_status == Status.INVALID and self._node is not None:
            self._node.get_logger().info(f"{self.name} terminated ({new_status.name})")
