"""Nav2's ROS-free control nodes (``nav2_behavior_tree``, Jazzy), each with its declaration.

RecoveryNode, PipelineSequence and RoundRobin:

- :class:`RecoveryNode` ticks its first child; when it fails, the second child (the
  recovery) runs, then the first again, up to ``number_of_retries`` recoveries.
- :class:`PipelineSequence` ticks every child up to the furthest one that has been
  running, every tick, so earlier stages keep being re-ticked while a later one runs.
- :class:`RoundRobin` ticks one child at a time, moving to the next after each
  completion and remembering where it stopped across runs.
"""

from __future__ import annotations

from collections.abc import Sequence as Children

from sar_framework.engine.kind_plugin import (
    children_attr,
    control_kind,
    node_kind,
)
from sar_framework.engine.nodes.control_kinds import int_port
from sar_framework.engine.nodes.controls.base import Behaviour, BtControl, Outcome, Steps

_RECOVERY = control_kind(
    "RecoveryNode", "Nav2: the first child; when it fails, the second (recovery), then the "
    "first again.",
    int_port("number_of_retries", "Recoveries allowed before failing.", default=1, minimum=0),
    children=children_attr(2, 2, "The action, then its recovery."), symbol="{o}",
    reads=("number_of_retries",), reports="recovery")


@node_kind(_RECOVERY)
class RecoveryNode(BtControl):
    """Nav2 ``RecoveryNode``: the first child, recovered by the second up to N times.

    A skipped first child skips the node; a skipped recovery fails it (not counted as
    a retry); a failed recovery fails it.

    Args:
        name: The behaviour's name.
        children: The action and its recovery.
        number_of_retries: Recoveries allowed before the node fails.

    Raises:
        ValueError: Not exactly 2 children.
    """

    def __init__(self, name: str, children: Children[Behaviour],
                 number_of_retries: int = 1) -> None:
        if len(children) != 2:
            raise ValueError(f"RecoveryNode '{name}' must have exactly 2 children, "
                             f"got {len(children)}")
        super().__init__(name, children)
        self.number_of_retries = number_of_retries
        self.index = 0
        self.retries = 0

    def read_port(self, port: str, value: int) -> None:
        """Take ``number_of_retries`` read from its entry."""
        self.number_of_retries = value

    def control(self) -> Steps:
        """Alternate the action and its recovery within the tick until one must wait."""
        while self.index < 2 and self.retries <= self.number_of_retries:
            result = yield from self.tick_child(self.children[self.index])
            if result is Outcome.RUNNING:
                return result
            if self.index == 0:
                if result is Outcome.FAILURE and self.retries < self.number_of_retries:
                    self.halt_child(0)
                    self.index = 1
                    continue
                if result is Outcome.SUCCESS:
                    self.halt_child(1)
                self.halt()
                return result
            if result is Outcome.SKIPPED:
                self.index = 0
                self.halt_child(1)
                return Outcome.FAILURE
            if result is Outcome.SUCCESS:
                self.halt_child(1)
                self.retries += 1
                self.index = 0
                continue
            self.halt()
            return Outcome.FAILURE
        self.halt()
        return Outcome.FAILURE

    def halt(self) -> None:
        """Back to the first child with no retries used; children halted and reset."""
        super().halt()
        self.retries = 0
        self.index = 0


@node_kind(control_kind("PipelineSequence", "Nav2: every tick, re-tick the earlier children "
                        "while a later one runs.", symbol="[-]"))
class PipelineSequence(BtControl):
    """Nav2 ``PipelineSequence``: re-tick every earlier child while a later one runs.

    Args:
        name: The behaviour's name.
        children: The stages, in order.
    """

    marks_running = False

    def __init__(self, name: str, children: Children[Behaviour]) -> None:
        super().__init__(name, children)
        self.last_ticked = 0

    def control(self) -> Steps:
        """Tick from the first child up to the furthest one that ran."""
        skipped = 0
        for index, child in enumerate(self.children):
            result = yield from self.tick_child(child)
            if result is Outcome.FAILURE:
                self.reset_children()
                self.last_ticked = 0
                return result
            if result is Outcome.SKIPPED:
                skipped += 1
            elif result is Outcome.RUNNING and index >= self.last_ticked:
                self.last_ticked = index
                return result
        self.reset_children()
        self.last_ticked = 0
        return Outcome.SKIPPED if skipped == len(self.children) else Outcome.SUCCESS

    def halt(self) -> None:
        """Back to the first stage; children halted and reset."""
        super().halt()
        self.last_ticked = 0


@node_kind(control_kind("RoundRobin", "Nav2: one child at a time, the next one after each "
                        "completion.", symbol="{o}"))
class RoundRobin(BtControl):
    """Nav2 ``RoundRobin``: one child at a time, the next one after each completion.

    It succeeds with the first child that succeeds (the next run starts after it) and
    fails when every child failed (or was skipped) in a row.

    Args:
        name: The behaviour's name.
        children: The children, in turn.
    """

    def __init__(self, name: str, children: Children[Behaviour]) -> None:
        super().__init__(name, children)
        self.index = 0
        self.failed = 0

    def control(self) -> Steps:
        """Tick children in turn from ``index`` until one succeeds or runs."""
        count = len(self.children)
        skipped = 0
        while self.failed + skipped < count:
            result = yield from self.tick_child(self.children[self.index])
            if result is Outcome.RUNNING:
                return result
            self.index = (self.index + 1) % count
            if result is Outcome.SUCCESS:
                self.failed = 0
                self.reset_children()
                return result
            if result is Outcome.FAILURE:
                self.failed += 1
            else:
                skipped += 1
        all_skipped = skipped == count
        self.halt()
        return Outcome.SKIPPED if all_skipped else Outcome.FAILURE

    def halt(self) -> None:
        """Back to the first child; children halted and reset."""
        super().halt()
        self.index = 0
        self.failed = 0
