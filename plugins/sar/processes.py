"""The search-and-rescue app's processes: the detect and report servers, the coordinator.

Both servers start before the runner, on its clock (a run of named robots: one detect
server per robot, one report server at the base, and the zone coordinator when the tree
bids for zones, :mod:`sar_plugins.sar.fleet.processes`). The detect server reads ``survivors_file``
(``sar-tree run --survivors``, the launch's ``survivors_file``); the report server writes
``report_file``, ``reports.jsonl`` in the run's folder unless named otherwise.
"""

from __future__ import annotations

import json
from collections.abc import Mapping, Sequence
from pathlib import Path

from sar_plugins.sar.fleet.processes import COORDINATOR_KIND, coordinator
from sar_plugins.sar.servers.params import DETECT_PARAMETERS, REPORT_PARAMETERS

from sar_framework.app import AppOption, AppProcess, ServiceCall
from sar_framework.mission.processes import MissionSettings, ParamValue, Process

REPORT_FILE = "reports.jsonl"
"""The report server's acknowledged reports, in the run's folder."""

PROCESS_KINDS = (
    AppProcess("detect", "the detect server", DETECT_PARAMETERS,
               "plugins/sar/servers/params.py", "--no-detect-server",
               "do not start the search-and-rescue detect server (fault injection)",
               per_robot=True),
    AppProcess("report", "the report server", REPORT_PARAMETERS,
               "plugins/sar/servers/params.py", "--no-report-server",
               "do not start the report server (fault injection)"),
    COORDINATOR_KIND,
)
"""What ``sar-tree run`` and the docs know of the app's processes."""


def _check_survivors(path: str) -> str | None:
    from sar_plugins.sar.servers.survivors import SurvivorsFileError, load_survivors

    try:
        load_survivors(path)
    except SurvivorsFileError as err:
        return str(err)
    return None


OPTIONS = (
    AppOption("--survivors", "detect", "survivors_file", "survivor table",
              "survivor table for the detect server (default: config/survivors.yaml)",
              _check_survivors),
)
"""``sar-tree run --survivors FILE``: the detect server's table."""

REPORT_EVENTS_TOPIC = "/report_survivor/_service_event"
RECORDED_TOPICS = (
    ("/detect_survivor/_service_event", "sar_interfaces/srv/DetectSurvivor_Event"),
    (REPORT_EVENTS_TOPIC, "sar_interfaces/srv/ReportSurvivor_Event"),
)
"""The servers' introspection events, kept by a recording."""
RUN_FILES = (REPORT_FILE,)
"""What the servers write in the run's folder."""


def replayed_reports(calls: Mapping[str, Sequence[ServiceCall]], folder: Path) -> None:
    """``reports.jsonl`` rebuilt from a recording: the report server's acknowledged calls.

    Args:
        calls: The recording's service calls, by ``_service_event`` topic.
        folder: The replay's report folder.
    """
    lines = [{"survivor_id": call.request.survivor_id,
              "frame_id": call.request.location.header.frame_id,
              "x": call.request.location.point.x, "y": call.request.location.point.y,
              "stamp": call.stamp_s}
             for call in calls.get(REPORT_EVENTS_TOPIC, ()) if call.response.acknowledged]
    (folder / REPORT_FILE).write_text("".join(json.dumps(line) + "\n" for line in lines),
                                      encoding="utf-8")


def _server(settings: MissionSettings, label: str, executable: str) -> Process:
    parameters: dict[str, ParamValue] = {"use_sim_time": settings.use_sim_time}
    if label == "report" and settings.run_folder:
        parameters["report_file"] = str(Path(settings.run_folder) / REPORT_FILE)
    module = "sar_plugins.sar.servers." + label + "_survivor_server"
    return Process(label, executable, module, (), parameters)


def server_processes(settings: MissionSettings) -> list[Process]:
    """The servers and the coordinator, in start order (``settings.extra`` sets their files).

    Args:
        settings: What the mission starts.

    Returns:
        Their descriptions.
    """
    return [_server(settings, "detect", "sar-detect-survivor-server"),
            _server(settings, "report", "sar-report-survivor-server"), *coordinator(settings)]
