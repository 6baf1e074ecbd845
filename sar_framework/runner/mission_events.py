"""The runner's event emitter: wired to the topic, ``events.jsonl`` and the zone manager."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

from sar_framework.events.emitter import EventEmitter
from sar_framework.events.event import EventKind
from sar_framework.events.jsonl import EVENTS_FILE, EventFileWriter

if TYPE_CHECKING:
    from rclpy.node import Node

    from sar_framework.engine.api import LoadedTree
    from sar_framework.mission.params import MissionParams
    from sar_framework.runner.settings import RunnerSettings


def mission_events(node: Node, settings: RunnerSettings, loaded: LoadedTree,
                   mission: MissionParams, wall_start: float,
                   ) -> tuple[EventEmitter, EventFileWriter | None]:
    """The mission's event emitter: to the topic, to ``events.jsonl`` beside the status file.

    Args:
        node: The runner's node (its clock stamps the events; it publishes them).
        settings: The runner's parameters (``status_file`` places the JSON-lines file).
        loaded: The tree (an event's node is named by its uid and kind).
        mission: The mission (its zone manager's reached/unreached zones become events).
        wall_start: ``time.monotonic()`` when the runner started.

    Returns:
        The emitter and the file writer (None without a status file), to close at the end.
    """
    from sar_framework.runner.event_topic import EventPublisher

    clock = node.get_clock()
    kinds = {n.uid: n.kind for n in loaded.spec.nodes()}
    emitter = EventEmitter(
        [EventPublisher(node)], sim_now=lambda: clock.now().nanoseconds / 1e9,
        wall_start=wall_start,
        nodes={uid: (b, kinds.get(uid, "")) for uid, b in loaded.behaviours.items()})
    writer = None
    if settings.status_file:
        writer = EventFileWriter(Path(settings.status_file).with_name(EVENTS_FILE))
        emitter.add_sink(writer)

    def zone_event(kind: EventKind, zone: dict[str, Any]) -> None:
        said = (f"Reached {zone['id']}." if kind == EventKind.ZONE_REACHED
                else f"{zone['id']} not reached; the mission moves on.")
        position = (zone["x"], zone["y"]) if "x" in zone else None
        emitter.emit(kind, zone_id=zone["id"], message=said, position=position)

    mission.zone_manager.observe(zone_event)
    return emitter, writer
