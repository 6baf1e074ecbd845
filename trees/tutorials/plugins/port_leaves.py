"""Two ROS-free leaves with ports, for tutorial 9, "Ports, blackboard and scripts".

They pass data on the blackboard, BehaviorTree.CPP's way, instead of referring to each
other by id (tutorial 3)::

    Drive   RUNNING one tick, then spends `cost` of the `battery` entry (FAILURE if short)
    Scan    counts the `sightings` in `zone` and writes the count to `found`

A tree loads this file with ``plugins: [plugins/port_leaves.py]``.
"""

from __future__ import annotations

from typing import Any

import py_trees
from py_trees.common import Status

from sar_framework.engine.plugin import leaf
from sar_framework.engine.ports import BidirectionalPort, InputPort, OutputPort


@leaf(ports=[
    InputPort("zone", str, description="The zone to drive to."),
    InputPort("cost", float, default=25.0, description="Battery percent the drive uses."),
    BidirectionalPort("battery", float, default="{=}",
                      description="The battery's charge in percent; the drive lowers it."),
])
class Drive(py_trees.behaviour.Behaviour):
    """RUNNING for one tick, then lower `battery` by `cost`: SUCCESS, or FAILURE if short."""

    def __init__(self, name: str, *, ports: Any) -> None:
        super().__init__(name)
        self.ports = ports
        self.started = False

    def initialise(self) -> None:
        """Every fresh start drives from scratch."""
        self.started = False

    def update(self) -> Status:
        """RUNNING on the first tick; then spend the charge, or fail when it is short."""
        zone = self.ports.get("zone")
        if not self.started:
            self.started = True
            self.feedback_message = f"driving to {zone}"
            return Status.RUNNING
        battery, cost = self.ports.get("battery"), self.ports.get("cost")
        if battery < cost:
            self.feedback_message = f"{battery:g}% left, {zone} needs {cost:g}%"
            return Status.FAILURE
        self.ports.set("battery", battery - cost)
        self.feedback_message = f"at {zone}"
        return Status.SUCCESS


@leaf(ports=[
    InputPort("zone", str, description="The zone to scan."),
    InputPort("sightings", list, default=[],
              description="Where survivors were seen, one zone per survivor ('a;b;b')."),
    OutputPort("found", int, description="How many survivors are in the zone."),
])
class Scan(py_trees.behaviour.Behaviour):
    """Count the survivors `sightings` lists in `zone`; write the count to `found`; SUCCESS."""

    def __init__(self, name: str, *, ports: Any) -> None:
        super().__init__(name)
        self.ports = ports

    def update(self) -> Status:
        """Count, write `found`, SUCCESS."""
        zone = self.ports.get("zone")
        found = self.ports.get("sightings").count(zone)
        self.ports.set("found", found)
        self.feedback_message = f"{found} in {zone}"
        return Status.SUCCESS
