"""The runner's event emitter: wired to the topic, ``events.jsonl`` and the apps."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

from sar_framework.events.emitter import EventEmitter
from sar_framework.events.jsonl import EVENTS_FILE, EventFileWriter

if TYPE_CHECKING:
    from rclpy.node import Node

    from sar_framework.app import AppRun
    from sar_framework.engine.api import LoadedTree
    from sar_framework.runner.settings import RunnerSettings


def mission_events(node: Node, settings: RunnerSettings, loaded: LoadedTree,
                   apps: Sequence[AppRun], wall_start: float,
                   ) -> tuple[EventEmitter, EventFileWriter | None]:
    """The mission's event emitter: to the topic, to ``events.jsonl`` beside the status file.

    Args:
        node: The runner's node (its clock stamps the events; it publishes them).
        settings: The runner's parameters (``status_file`` places the JSON-lines file).
        loaded: The tree (an event's node is named by its uid and kind).
        apps: The tree's apps (each wires its own events to the emitter).
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

    for app in apps:
        if app.observe is not None:
            app.observe(emitter)
    return emitter, writer
