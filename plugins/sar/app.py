"""The search-and-rescue :class:`~sar_framework.app.App`: what it adds to the core.

- context: the mission's ``zone_manager``, read from ``zone_order``, ``zones.*`` and
  ``base_station.*`` (so every tree with a zone leaf uses this app);
- parameters: those, checked whole (:func:`~sar_framework.mission.params_check.mission_problems`),
  from ``config/mission_params.yaml`` when ``sar-tree run`` names no file;
- processes: the detect and report servers, started before the runner; with several robots
  a detect server each, their homes, and the zone coordinator (:mod:`sar_plugins.sar.fleet`);
- events: the zone and survivor kinds (:mod:`.events`), and the status's current zone;
- the report, ``mission.png``, the studio and ``sar-tree watch``: :mod:`.report`,
  :mod:`.figure`, :mod:`.studio` (a fleet's: who searched which zone, the auction).
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

from sar_plugins.sar.events import SAR_KINDS, SarKind
from sar_plugins.sar.figure import mission_figure
from sar_plugins.sar.fleet.processes import robot_parameters, spawn_around
from sar_plugins.sar.fleet.report import fleet_figure, fleet_report
from sar_plugins.sar.params import MISSION_PARAMETERS, mission_problems, zone_positions
from sar_plugins.sar.processes import (
    OPTIONS,
    PROCESS_KINDS,
    RECORDED_TOPICS,
    RUN_FILES,
    replayed_reports,
    server_processes,
)
from sar_plugins.sar.report import mission_report, progress_line, summary_parts
from sar_plugins.sar.studio import MARKS, frame, layout, status_text

from sar_framework.app import App, AppRun
from sar_framework.app.app import checkout_file
from sar_framework.events.event import EventKind

if TYPE_CHECKING:
    from rclpy.node import Node
    from sar_plugins.sar.zone_manager import ZoneManager

    from sar_framework.events.emitter import EventEmitter
    from sar_framework.mission.params_file import KeyLocation

PARAMS_FILE = "config/mission_params.yaml"
"""The mission parameter file when none is named (the checkout's when the folder has none)."""
_CHECKOUT = Path(__file__).resolve().parents[2]


def _params_file() -> str:
    return checkout_file(PARAMS_FILE, _CHECKOUT)


def zone_of(zone_manager: ZoneManager) -> dict[str, Any] | None:
    """The zone the mission is at, as ``{"id", "index", "total"}`` (the status's ``zone``).

    Args:
        zone_manager: The mission's zone manager.

    Returns:
        The zone, or None once every zone is done.
    """
    if not zone_manager.has_remaining():
        return None
    return {"id": zone_manager.current_zone()["id"], "index": zone_manager.current_index(),
            "total": zone_manager.total_zones()}


def _start(node: Node, source: str, locations: Mapping[str, KeyLocation]) -> AppRun:
    """Read the zones from the runner's node: the ZoneManager, its events, its status."""
    from sar_plugins.sar.params import read_mission_params

    mission_file = locations.get("zone_order")
    source = mission_file.file if mission_file else source
    mission = read_mission_params(node, source=source, locations=locations)
    for zone_id in mission.unused_zones:
        node.get_logger().warning(f"{source}: zones.{zone_id} is defined but not in "
                                  "zone_order (it will not be visited)")
    manager = mission.zone_manager

    def observe(emitter: EventEmitter) -> None:
        def zone_event(kind: EventKind, zone: dict[str, Any]) -> None:
            said = (f"Reached {zone['id']}." if kind == SarKind.ZONE_REACHED
                    else f"{zone['id']} not reached; the mission moves on.")
            position = (zone["x"], zone["y"]) if "x" in zone else None
            emitter.emit(kind, zone_id=zone["id"], message=said, position=position)

        manager.observe(zone_event)

    return AppRun({"zone_manager": manager}, observe, lambda: {"zone": zone_of(manager)})


APP = App(
    name="search_and_rescue",
    provides=("zone_manager",),
    parameters=MISSION_PARAMETERS,
    params_file=_params_file,
    check=mission_problems,
    start=_start,
    processes=server_processes,
    process_kinds=PROCESS_KINDS,
    options=OPTIONS,
    places=zone_positions,
    recorded_topics=RECORDED_TOPICS,
    run_files=RUN_FILES,
    replayed=replayed_reports,
    event_kinds={kind.value: kind.name.lower().replace("_", " ") for kind in SAR_KINDS},
    progress=progress_line,
    summary=summary_parts,
    report=mission_report,
    layout=layout,
    marks=MARKS,
    frame=frame,
    status_text=status_text,
    figure=mission_figure,
    robot_parameters=robot_parameters,
    spawn_around=spawn_around,
    fleet_report=fleet_report,
    fleet_figure=fleet_figure,
)
"""The search-and-rescue app."""
