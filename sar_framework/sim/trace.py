"""The robot's trace: sampled poses and goal events as JSON Lines, plus the odometer.

Plain Python (no ROS). One JSON object per line, every line with ``sim_s``::

    {"sim_s": 0.0, "event": "start", "x": 0.0, "y": 0.0, "yaw": 0.0, "speed": 20.0}
    {"sim_s": 0.2, "x": 0.1, "y": 0.0, "yaw": 0.0, "path_m": 0.1}
    {"sim_s": 0.4, "event": "accepted", "goal": 1, "x": -3.0, "y": 3.0, "yaw": 0.0}
    {"sim_s": 21.6, "event": "succeeded", "goal": 1, "x": -3.0, "y": 3.0, "yaw": 0.0, ...}
    {"sim_s": 160.0, "event": "end", "path_m": 38.2, "goals": 5, ...}

Pose lines are written at most every ``sample_period_s`` simulated seconds and only while
the robot moves (plus one at every goal event), so an idle robot adds nothing. Event lines
carry the goal pose; pose lines the robot's. ``path_m`` is the distance travelled so far.
"""

from __future__ import annotations

import json
import math
import threading
import time
from pathlib import Path
from typing import IO, Any


class TraceWriter:
    """Writes the trace file; thread-safe; flushes every ``flush_period_s`` wall seconds.

    Args:
        path: Output file (truncated; its folder is created).
        sample_period_s: Minimum simulated seconds between two pose lines.
        flush_period_s: Maximum wall seconds a written line may wait in the buffer.
    """

    def __init__(
        self, path: str | Path, sample_period_s: float = 0.2, flush_period_s: float = 1.0
    ) -> None:
        self.path = Path(path)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self._file: IO[str] | None = self.path.open("w", encoding="utf-8")
        self._lock = threading.Lock()
        self._sample_period_s = sample_period_s
        self._flush_period_s = flush_period_s
        self._last_sample_s = -math.inf
        self._last_pose: tuple[float, float, float] | None = None
        self._last_flush = time.monotonic()

    def _write(self, record: dict[str, Any]) -> None:
        with self._lock:
            if self._file is None:
                return
            self._file.write(json.dumps(record, separators=(", ", ": ")) + "\n")
            now = time.monotonic()
            if now - self._last_flush >= self._flush_period_s:
                self._file.flush()
                self._last_flush = now

    def pose(self, sim_s: float, x: float, y: float, yaw: float, path_m: float) -> None:
        """Record the robot's pose if it moved and the sampling period has passed.

        Args:
            sim_s: Simulated time, seconds.
            x: Metres.
            y: Metres.
            yaw: Radians.
            path_m: Distance travelled so far, metres.
        """
        pose = (round(x, 4), round(y, 4), round(yaw, 4))
        if pose == self._last_pose or sim_s - self._last_sample_s < self._sample_period_s:
            return
        self._last_sample_s = sim_s
        self._last_pose = pose
        self._write({"sim_s": round(sim_s, 4), "x": pose[0], "y": pose[1], "yaw": pose[2],
                     "path_m": round(path_m, 4)})

    def event(self, sim_s: float, event: str, **fields: Any) -> None:
        """Record an event line (``start``, ``accepted``, ``succeeded``, ``end``...).

        Args:
            sim_s: Simulated time, seconds.
            event: The event name.
            **fields: Extra JSON-serialisable fields (floats are rounded to 4 places).
        """
        record: dict[str, Any] = {"sim_s": round(sim_s, 4), "event": event}
        for key, value in fields.items():
            record[key] = round(value, 4) if isinstance(value, float) else value
        self._write(record)
        self.flush()  # at once: `sar-tree run` times its stop by a goal's end

    def flush(self) -> None:
        """Write buffered lines to disk."""
        with self._lock:
            if self._file is not None:
                self._file.flush()
                self._last_flush = time.monotonic()

    def close(self) -> None:
        """Flush and close; later writes are ignored."""
        with self._lock:
            if self._file is not None:
                self._file.close()
                self._file = None


def read_trace(path: str | Path) -> list[dict[str, Any]]:
    """Read a trace file back (for reports and tests).

    Args:
        path: The JSON Lines file.

    Returns:
        One dict per line, in order.
    """
    lines = Path(path).read_text(encoding="utf-8").splitlines()
    return [json.loads(line) for line in lines if line.strip()]
