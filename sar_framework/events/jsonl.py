"""``events.jsonl``: the event stream as JSON lines in the report folder (no ROS).

The runner writes one :meth:`~.event.MissionEvent.to_json` line per event and flushes it at
once (:class:`EventFileWriter`), so ``sar-tree run`` follows the mission by reading the file
as it grows (:class:`EventFileFollower`); a line still being written is read on the next
poll. :func:`read_events` reads a whole file afterwards (``mission.json``, tests).
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import IO, Any

from sar_framework.events.event import EventFormatError, MissionEvent, event_from_dict

EVENTS_FILE = "events.jsonl"
"""The file's name in the report folder."""


class EventFileWriter:
    """Appends events to a JSON-lines file, one flushed line each.

    Args:
        path: The file (its folder is created).
        append: Keep what the file holds (else it is truncated).
    """

    def __init__(self, path: str | Path, *, append: bool = False) -> None:
        self.path = Path(path)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self._file: IO[str] | None = self.path.open("a" if append else "w", encoding="utf-8")

    def __call__(self, event: MissionEvent) -> None:
        """Write ``event`` (ignored once closed)."""
        if self._file is None:
            return
        self._file.write(event.to_json() + "\n")
        self._file.flush()

    def close(self) -> None:
        """Close the file; later events are ignored."""
        if self._file is not None:
            self._file.close()
            self._file = None


class JsonLinesFollower:
    """Reads the JSON values added to a JSON-lines file since the last :meth:`poll`.

    A missing file is an empty stream (its writer has not started yet); a line still
    being written is read once complete; a line that is not JSON is counted in
    :attr:`rejected` and skipped.

    Args:
        path: The file.
    """

    def __init__(self, path: str | Path) -> None:
        self.path = Path(path)
        self.rejected = 0
        self._offset = 0
        self._partial = b""

    def poll(self) -> list[Any]:
        """The values whose lines were completed since the last call, in file order."""
        try:
            with self.path.open("rb") as handle:
                handle.seek(self._offset)
                data = handle.read()
        except OSError:
            return []
        self._offset += len(data)
        *lines, self._partial = (self._partial + data).split(b"\n")
        values = []
        for line in lines:
            if not line.strip():
                continue
            try:
                values.append(json.loads(line.decode("utf-8", "replace")))
            except ValueError:
                self.rejected += 1
        return values


class EventFileFollower(JsonLinesFollower):
    """Reads the events added to ``events.jsonl`` since the last :meth:`poll`.

    A line that is not an event is counted in :attr:`rejected` and skipped.

    Args:
        path: The file.
    """

    def poll(self) -> list[MissionEvent]:  # type: ignore[override]
        """The events whose lines were completed since the last call, in file order."""
        events = []
        for value in super().poll():
            try:
                events.append(event_from_dict(value))
            except EventFormatError:
                self.rejected += 1
        return events


def read_events(path: str | Path) -> list[MissionEvent]:
    """Every complete event line of a file (a missing file has none).

    Args:
        path: The file.
    """
    return EventFileFollower(path).poll()


def read_json_lines(path: str | Path) -> list[dict[str, Any]]:
    """Every JSON object line of a file (reports, traces, the coordinator's events).

    A missing file has none; a line that is not a JSON object (one cut short by a kill, or
    being written as it is read) is skipped.

    Args:
        path: The file.
    """
    try:
        text = Path(path).read_text(encoding="utf-8")
    except OSError:
        return []
    records = []
    for line in text.splitlines():
        try:
            record = json.loads(line)
        except ValueError:
            continue
        if isinstance(record, dict):
            records.append(record)
    return records
