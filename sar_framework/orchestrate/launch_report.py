"""The report of a mission started by ``ros2 launch``: the same files as ``sar-tree run``'s.

When the launch's runner exits, :func:`write_launch_report` writes ``mission.json``,
``mission.png`` and ``tree.svg`` into the run's folder (where the runner's status and
events, and the simulator's trace, already are), from the runner's exit code, as
``sar-tree run`` does (:func:`~sar_framework.orchestrate.outcome.runner_exit_outcome`).
"""

from __future__ import annotations

import time
from pathlib import Path

from sar_framework.app import App
from sar_framework.events.jsonl import EVENTS_FILE, read_events
from sar_framework.mission.processes import MissionSettings
from sar_framework.orchestrate.outcome import read_status, runner_exit_outcome


def write_launch_report(settings: MissionSettings, apps: list[App], exit_code: int,
                        started: float) -> list[Path]:
    """Write the run's report into its folder; return the files written.

    Args:
        settings: What the launch started (its run folder is the status file's).
        apps: The tree's apps (their parts of the report).
        exit_code: The runner's exit code.
        started: ``time.monotonic()`` when the launch described the mission.
    """
    from sar_framework.engine.api import validate
    from sar_framework.report import MissionInputs, write_report

    folder = Path(settings.status_file).parent
    outcome = runner_exit_outcome(exit_code, read_events(folder / EVENTS_FILE),
                                  read_status(folder), "see the runner's log")
    spec = validate(settings.tree, plugin_paths=settings.plugin_paths).spec
    return write_report(MissionInputs(
        report_dir=folder, tree=settings.tree, params_file=settings.params_file, spec=spec,
        outcome=outcome.status, reason=outcome.reason,
        wall_duration_s=time.monotonic() - started, apps=apps))
