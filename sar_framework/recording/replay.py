"""``sar-tree replay FILE.mcap``: the mission report drawn again from a recording alone.

The recording is decoded (:mod:`.readback`) into the files a live run leaves, then
:func:`sar_framework.report.write_report` writes ``mission.json``, ``mission.png`` and
``tree.svg`` exactly as after ``sar-tree run``; the outcome is the recorded ``completion``
event's. The tree, its includes, its local plugins and the parameter file come from the
recording's attachments alone: they are written into ``DIR/recorded_files/``
(:mod:`.sources`) and the tree is built from there. The apps are the installed ones and
those the recorded plugins define (a tree's ``plugins:`` app), so the report, and the
studio's replay, speak of the same app as the run did.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

from sar_framework.events.event import EventKind, MissionEvent
from sar_framework.recording.readback import (
    Recording,
    RecordingError,
    read_recording,
    write_report_inputs,
)
from sar_framework.recording.sources import SourcesError, extract

if TYPE_CHECKING:
    from sar_framework.app import App

EXIT_OK = 0
EXIT_FAILURE = 1
EXIT_USAGE = 2
#: The folder of the report where the recorded tree files and plugin sources are written.
SOURCES_FOLDER = "recorded_files"


def configure(parser: argparse.ArgumentParser) -> None:
    """Add ``sar-tree replay``'s arguments to ``parser``."""
    parser.add_argument("recording", metavar="FILE.mcap", help="a recording of sar-tree run")
    parser.add_argument("--report-dir", metavar="DIR",
                        help="where the report goes (default: FILE_replay/ beside the file)")


def outcome_of(events: Sequence[MissionEvent]) -> str:
    """The recorded ``completion`` event's ``SUCCESS`` / ``FAILURE``, else ``INTERRUPTED``."""
    completion = next((e for e in events if e.kind == EventKind.COMPLETION), None)
    if completion is not None and completion.status in ("SUCCESS", "FAILURE"):
        return completion.status
    return "INTERRUPTED"


@dataclass
class RecordedTree:
    """The tree of a recording, built again from the recording's files alone.

    Attributes:
        name: The tree file to name: where the recorded tree was ("" when unknown).
        file: Its copy from the recording, or None when the recording holds no tree.
        spec: The validated tree, or None (no tree, or it does not validate here).
        apps: The installed apps, then those the recorded plugins define that the tree uses.
        problems: Why the tree or its apps could not be had (warnings, in order).
    """

    name: str
    file: Path | None = None
    spec: Any = None
    apps: list[App] = field(default_factory=list)
    problems: list[str] = field(default_factory=list)


def recorded_tree(recording: Recording, folder: Path) -> RecordedTree:
    """Write the recorded tree files and plugin sources into ``folder``; build the tree.

    Args:
        recording: The decoded recording.
        folder: Where the files are written (created).

    Raises:
        RecordingError: The recording's files cannot be written out.
    """
    from sar_framework.app import AppError, apps_for, installed_apps
    from sar_framework.app.discovery import with_installed
    from sar_framework.engine.api import validate

    try:
        files = extract(recording.attachments, recording.metadata, folder)
    except SourcesError as err:
        raise RecordingError(f"{recording.path}: {err}") from None
    found = RecordedTree(recording.metadata.get("tree", ""), files.tree,
                         apps=installed_apps())
    if files.tree is None:
        found.problems.append("the recording holds no tree file; tree.svg is not drawn")
        return found
    found.name = found.name or str(files.tree)
    result = validate(files.tree, plugin_paths=files.plugin_paths)
    found.spec = result.spec
    if result.spec is None:
        found.problems += [str(d) for d in result.diagnostics]
        return found
    try:
        used = apps_for(result.spec, result.registry)
    except AppError as err:
        found.problems.append(str(err))
        return found
    found.apps = with_installed(used)
    return found


def replay(path: str | Path, report_dir: str | Path | None = None) -> list[Path]:
    """Write the report of a recorded mission.

    Args:
        path: The recording.
        report_dir: Where to write (default ``<stem>_replay`` beside the recording).

    Returns:
        The report files written.

    Raises:
        RecordingError: The file cannot be read as a mission recording.
    """
    from sar_framework.report import MissionInputs, write_report

    recording = read_recording(path)
    if not recording.statuses:
        raise RecordingError(f"{path}: no tree status in the recording "
                             "(was it recorded with sar-tree run --record?)")
    folder = Path(report_dir) if report_dir else \
        Path(path).with_name(f"{Path(path).stem}_replay")
    tree = recorded_tree(recording, folder / SOURCES_FOLDER)
    for problem in tree.problems:
        sys.stderr.write(f"sar-tree replay: warning: {problem}\n")
    files = write_report_inputs(recording, folder, tree.apps)
    inputs = MissionInputs(
        report_dir=folder, tree=tree.name, params_file=str(files.get("params", "")),
        spec=tree.spec, outcome=outcome_of(recording.events),
        wall_duration_s=recording.wall_duration_s, apps=tree.apps)
    return write_report(inputs)


def replay_command(args: argparse.Namespace) -> int:
    """``sar-tree replay``: return the exit code (0, or 2 for a file it cannot read)."""
    if not Path(args.recording).is_file():
        sys.stderr.write(f"sar-tree replay: error: recording not found: '{args.recording}'\n")
        return EXIT_USAGE
    try:
        written = replay(args.recording, args.report_dir)
    except RecordingError as err:
        sys.stderr.write(f"sar-tree replay: error: {err}\n")
        return EXIT_USAGE
    folder = written[0].parent if written else args.report_dir
    sys.stdout.write(f"sar-tree replay: report in {folder}/ "
                     f"({', '.join(p.name for p in written)})\n")
    return EXIT_OK
