"""Three ROS-free leaves for the tutorials (docs/tutorials/), in one short file.

Each is a plain :class:`py_trees.behaviour.Behaviour` marked with ``@leaf``; the
declaration is all the engine needs to validate a tree, generate the schema, list the
plugin in ``sar-tree plugins`` and call the constructor. A tree loads this file with
``plugins: [plugins/tutorial_leaves.py]`` (relative to the tree file).

They stand in for the mission's ROS leaves, so the tutorials can tick real trees
without ROS::

    Countdown   RUNNING for `ticks` ticks, then `result`     (like any action leaf)
    TakeId      a fresh survivor id on every tick             (like BroadcastSurvivorTF)
    ReportId    reports a TakeId leaf's id after a few ticks  (like NotifyBase)
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import py_trees
from py_trees.common import Status

from sar_framework.engine.plugin import Param, leaf

if TYPE_CHECKING:
    from sar_plugins.sar.zone_manager import ZoneManager


@leaf(
    params=[
        Param("ticks", int, default=2, minimum=0,
              description="How many ticks to stay RUNNING before finishing."),
        Param("result", str, default="success", enum=("success", "failure"),
              description="The status to finish with."),
    ]
)
class Countdown(py_trees.behaviour.Behaviour):
    """RUNNING for `ticks` ticks, then SUCCESS or FAILURE (`result`).

    Every fresh start (``initialise``) rewinds the countdown, so a decorator that
    restarts the leaf (retry, a reactive parent) sees the whole wait again.

    Args:
        name: The behaviour's name.
        ticks: Ticks to stay RUNNING.
        result: ``"success"`` or ``"failure"``.
    """

    def __init__(self, name: str, *, ticks: int, result: str) -> None:
        super().__init__(name)
        self.ticks = ticks
        self.result = Status.SUCCESS if result == "success" else Status.FAILURE
        self.left = ticks

    def initialise(self) -> None:
        """Rewind the countdown."""
        self.left = self.ticks

    def update(self) -> Status:
        """Count one tick down; finish with `result` at zero."""
        if self.left > 0:
            self.feedback_message = f"{self.left} to go"
            self.left -= 1
            return Status.RUNNING
        self.feedback_message = f"done ({self.result.name})"
        return self.result


@leaf(context=["zone_manager"])
class TakeId(py_trees.behaviour.Behaviour):
    """Take the next survivor id from the ZoneManager on every tick; SUCCESS.

    Like BroadcastSurvivorTF, every tick allocates a new id: tick it twice for one
    survivor and you have a duplicate.

    Args:
        name: The behaviour's name.
        zone_manager: The shared mission state (context object).
    """

    def __init__(self, name: str, *, zone_manager: ZoneManager) -> None:
        super().__init__(name)
        self.zone_manager = zone_manager
        self.taken: str | None = None

    def update(self) -> Status:
        """Allocate an id and return SUCCESS."""
        self.taken = self.zone_manager.next_survivor_id()
        self.feedback_message = f"took {self.taken}"
        return Status.SUCCESS


@leaf(
    params=[
        Param("taker", ref="TakeId", description="id of the TakeId leaf whose id to report."),
        Param("ticks", int, default=1, minimum=0,
              description="Ticks to stay RUNNING (waiting for the base) before SUCCESS."),
    ]
)
class ReportId(py_trees.behaviour.Behaviour):
    """Report the id the referenced TakeId leaf took: RUNNING for `ticks`, then SUCCESS.

    Like NotifyBase, it reads another leaf by reference instead of a blackboard.

    Args:
        name: The behaviour's name.
        taker: The TakeId behaviour (the engine passes the instance, not the id).
        ticks: Ticks to stay RUNNING.
    """

    def __init__(self, name: str, *, taker: TakeId, ticks: int) -> None:
        super().__init__(name)
        self.taker = taker
        self.ticks = ticks
        self.left = ticks
        self.reported: list[str] = []

    def initialise(self) -> None:
        """Start a fresh report."""
        self.left = self.ticks

    def update(self) -> Status:
        """Wait `ticks` ticks, then record the taker's current id."""
        if self.left > 0:
            self.left -= 1
            self.feedback_message = f"reporting {self.taker.taken}..."
            return Status.RUNNING
        self.reported.append(str(self.taker.taken))
        self.feedback_message = f"reported {self.taker.taken}"
        return Status.SUCCESS
