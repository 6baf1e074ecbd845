"""A durable JSON Lines record of acknowledged survivor reports.

One line per survivor id, appended and ``fsync``-ed before the caller answers, so an
acknowledged report survives a crash of the server right after it. On opening, the ids
already in the file are loaded, so a restarted server does not write a survivor twice. A
torn last line (a crash mid-write) is skipped and terminated so later lines stay whole.
"""

from __future__ import annotations

import json
import os
from dataclasses import dataclass
from pathlib import Path
from typing import IO, Any


@dataclass(frozen=True)
class OpenResult:
    """What :meth:`ReportLog.open` found in an existing file.

    Attributes:
        loaded: Survivor ids read back.
        unreadable_lines: 1-based numbers of lines that were not a report (skipped).
    """

    loaded: int
    unreadable_lines: tuple[int, ...]


class ReportLog:
    """Append-only, crash-safe store of survivor reports keyed by survivor id.

    Args:
        path: The JSON Lines file; created (with its folder) if missing.
    """

    def __init__(self, path: str | Path) -> None:
        self.path = Path(path)
        self._records: dict[str, dict[str, Any]] = {}
        self._handle: IO[str] | None = None
        self._torn = False  # a failed write may have left a partial line

    def open(self) -> OpenResult:
        """Load existing reports and open the file for appending.

        Returns:
            How many ids were loaded and which lines were unreadable.

        Raises:
            OSError: The file or its folder cannot be read, created or written.
        """
        self.path.parent.mkdir(parents=True, exist_ok=True)
        existed = self.path.exists()
        unreadable: list[int] = []
        needs_newline = False
        if existed:
            data = self.path.read_bytes()
            needs_newline = bool(data) and not data.endswith(b"\n")
            for number, line in enumerate(data.decode("utf-8", "replace").splitlines(), 1):
                if not line.strip():
                    continue
                try:
                    record = json.loads(line)
                    survivor_id = record["survivor_id"]
                except (ValueError, TypeError, KeyError):
                    unreadable.append(number)
                    continue
                if isinstance(survivor_id, str):
                    self._records.setdefault(survivor_id, record)
                else:
                    unreadable.append(number)
        self._handle = self.path.open("a", encoding="utf-8")
        if needs_newline:
            self._write_durably("\n")
        if not existed:
            self._sync_folder()
        return OpenResult(len(self._records), tuple(unreadable))

    def get(self, survivor_id: str) -> dict[str, Any] | None:
        """Return the recorded report for ``survivor_id``, or None."""
        return self._records.get(survivor_id)

    def __contains__(self, survivor_id: object) -> bool:
        return survivor_id in self._records

    def __len__(self) -> int:
        return len(self._records)

    def append(self, record: dict[str, Any]) -> bool:
        """Record a report unless its survivor id is already recorded.

        The line is flushed and fsync-ed before this returns.

        Args:
            record: A JSON-serialisable mapping with a ``survivor_id`` string.

        Returns:
            True when written, False when the id was already recorded.

        Raises:
            OSError: The write failed (the report is then not recorded).
            RuntimeError: :meth:`open` was not called.
        """
        survivor_id = record["survivor_id"]
        if survivor_id in self._records:
            return False
        line = json.dumps(record, sort_keys=True) + "\n"
        try:
            self._write_durably(("\n" if self._torn else "") + line)
        except OSError:
            self._torn = True
            raise
        self._torn = False
        self._records[survivor_id] = dict(record)
        return True

    def close(self) -> None:
        """Close the file (reports are already on disk)."""
        if self._handle is not None:
            self._handle.close()
            self._handle = None

    def _write_durably(self, text: str) -> None:
        if self._handle is None:
            raise RuntimeError("ReportLog.open() was not called")
        self._handle.write(text)
        self._handle.flush()
        os.fsync(self._handle.fileno())

    def _sync_folder(self) -> None:
        """Make the new file's directory entry durable too."""
        fd = os.open(self.path.parent, os.O_RDONLY)
        try:
            os.fsync(fd)
        finally:
            os.close(fd)
