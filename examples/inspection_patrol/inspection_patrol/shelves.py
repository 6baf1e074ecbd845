"""The inspection patrol's plugin: the ShelfGoal and ScanShelf leaves and the app.

The shelves are data (``shelves.yaml`` beside this file: each shelf's scanning pose).
ShelfGoal writes a shelf's pose to a goal entry; ScanShelf asks the scan server to scan it.
The app starts the scan server (``scan_server.py``, a program of its own) for a tree that
uses it, gives the leaves their context object and the report, the studio and the console
its words about shelves; the tree's ``plugins:`` imports this file by path.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import yaml
from py_trees.common import Status

from sar_framework.app import App, AppRun
from sar_framework.engine.plugin import Param, leaf
from sar_framework.engine.ports import InputPort, OutputPort
from sar_framework.events.emitter import NO_EVENTS, EventEmitter, events_from
from sar_framework.events.event import EventKind, MissionEvent
from sar_framework.leaves import (
    Leaf,
    PolledServiceCall,
    RosLeaf,
    ServiceLeaf,
    interface_type,
    service_params,
)
from sar_framework.mission.processes import MissionSettings, Process

SHELF_SCANNED = "shelf_scanned"
"""The app's event kind: one shelf scanned (field ``shelf``)."""
SHELF_GOAL = "shelf_goal"
"""The app's event kind: the next goal is a shelf's pose (field ``shelf``)."""


SCANNER = "inspection_patrol.scan_server"
"""The scan server's module (``python -m``), in the package this file is in."""


SHELVES_FILE = Path(__file__).with_name("shelves.yaml")
"""The shelves' data, one place: each shelf's name and the pose the robot scans it from."""
POSE_FIELDS = ("x", "y", "yaw")


class ShelfDataError(ValueError):
    """The shelves' data is unreadable or wrong; the message names the file and the field."""


def load_shelves(path: Path = SHELVES_FILE) -> dict[str, tuple[float, float, float]]:
    """Each shelf's scanning pose ``(x, y, yaw)``, by name, from ``path``.

    Args:
        path: A YAML mapping ``NAME: {x: ..., y: ..., yaw: ...}``.

    Returns:
        The poses, in the file's order.

    Raises:
        ShelfDataError: When the file is missing, not YAML, or a shelf or field is wrong.
    """
    try:
        data = yaml.safe_load(path.read_text(encoding="utf-8"))
    except (OSError, yaml.YAMLError) as exc:
        raise ShelfDataError(f"{path}: cannot read the shelves: {exc}") from None
    if not isinstance(data, dict) or not data:
        raise ShelfDataError(f"{path}: a mapping of shelf names to poses is needed")
    shelves: dict[str, tuple[float, float, float]] = {}
    for name, pose in data.items():
        if not isinstance(name, str) or not name.isidentifier():
            raise ShelfDataError(f"{path}: shelf {name!r}: a name is needed (letters, digits, _)")
        if not isinstance(pose, dict):
            raise ShelfDataError(f"{path}: shelf {name}: a pose {{x, y, yaw}} is needed, "
                                 f"got {pose!r}")
        for key in pose:
            if key not in POSE_FIELDS:
                raise ShelfDataError(f"{path}: shelf {name}: field {key!r}: unknown "
                                     f"(a pose has {', '.join(POSE_FIELDS)})")
        for key in POSE_FIELDS:
            if key not in pose:
                raise ShelfDataError(f"{path}: shelf {name}: field {key!r}: missing")
            value = pose[key]
            if isinstance(value, bool) or not isinstance(value, (int, float)):
                raise ShelfDataError(f"{path}: shelf {name}: field {key!r}: a number is "
                                     f"needed, got {value!r}")
        shelves[name] = (float(pose["x"]), float(pose["y"]), float(pose["yaw"]))
    return shelves


class Inspection:
    """What the patrol has scanned so far (the app's context object)."""

    def __init__(self) -> None:
        self.scanned: list[str] = []


@leaf(params=[Param("frame_id", str, default="map", description="Frame of the pose.")],
      ports=[InputPort("shelf", str, description="The shelf's name, in the shelves' data."),
             OutputPort("goal", "geometry_msgs/msg/PoseStamped",
                        description="Where the robot stands to scan the shelf.")])
class ShelfGoal(Leaf):
    """Write the pose to scan ``shelf`` from (:data:`SHELVES_FILE`) to ``goal``; SUCCESS.

    The data is read when the tree is set up (a wrong file or field stops the run there);
    a shelf the data does not name is FAILURE, saying which shelves it names.

    Attributes:
        frame_id: Frame of the pose (declared param).
        ports: ``shelf`` (read) and ``goal`` (written).
    """

    frame_id: str
    ports: Any

    def __init__(self, name: str, **declared: Any) -> None:
        super().__init__(name, **declared)
        self.poses: dict[str, tuple[float, float, float]] = {}
        self._events: EventEmitter = NO_EVENTS

    def setup(self, **kwargs: Any) -> None:
        """Read the shelves' data; keep the event emitter ``setup(events=...)`` gives."""
        self._events = events_from(kwargs)
        self.poses = load_shelves(SHELVES_FILE)

    def update(self) -> Status:
        """Write the shelf's pose to ``goal`` (FAILURE for a shelf the data lacks)."""
        shelf = self.ports.get("shelf")
        if shelf not in self.poses:
            self.feedback_message = (f"{SHELVES_FILE.name}: no shelf {shelf!r} "
                                     f"(it has {', '.join(self.poses)})")
            return Status.FAILURE
        x, y, yaw = self.poses[shelf]
        self.ports.set("goal", _pose(x, y, yaw, self.frame_id))
        self.feedback_message = f"shelf {shelf} at ({x:.2f}, {y:.2f})"
        self._events.emit(SHELF_GOAL, source=self, message=self.feedback_message, shelf=shelf)
        return Status.SUCCESS


def _pose(x: float, y: float, yaw: float, frame_id: str) -> Any:
    """A ``geometry_msgs/PoseStamped`` at ``(x, y)`` facing ``yaw``; Nav2 fills the stamp."""
    from geometry_msgs.msg import PoseStamped

    pose = PoseStamped()
    pose.header.frame_id = frame_id
    pose.pose.position.x, pose.pose.position.y = x, y
    pose.pose.orientation.z, pose.pose.orientation.w = math.sin(yaw / 2), math.cos(yaw / 2)
    return pose


@leaf(params=[*service_params("scan_shelf", server_timeout_s=5.0, response_timeout_s=5.0)],
      ports=[InputPort("shelf", str, description="The shelf's name.")],
      context=["inspection"])
class ScanShelf(ServiceLeaf):
    """Ask the app's scan server to scan ``shelf``; record a ``shelf_scanned`` event.

    The server offers a ``std_srvs/srv/Trigger`` service per shelf (``scan_shelf/A``): the
    request carries no fields, the service's name says which shelf. The leaf reads
    ``shelf`` each time it starts and keeps a client per shelf it has asked.

    Attributes:
        ports: ``shelf`` (read).
        inspection: The app's :class:`Inspection` (context object).
    """

    service_type = "std_srvs/srv/Trigger"
    ports: Any
    inspection: Inspection

    def __init__(self, name: str, **declared: Any) -> None:
        super().__init__(name, **declared)
        self.prefix = self.service_name
        self.shelf = ""
        self._calls: dict[str, PolledServiceCall] = {}

    def setup(self, **kwargs: Any) -> None:
        """Take the node and the event emitter; clients are made per shelf when asked."""
        RosLeaf.setup(self, **kwargs)
        self._srv = interface_type(self.service_type)

    def initialise(self) -> None:
        """Read ``shelf`` and use that shelf's client (made on its first use)."""
        self.shelf = str(self.ports.get("shelf"))
        self.service_name = f"{self.prefix}/{self.shelf}"  # the shelf's own service
        if self.shelf not in self._calls:
            self._calls[self.shelf] = PolledServiceCall(
                self.node, self._srv, self.service_name,
                server_timeout_s=self.server_timeout_s,
                response_timeout_s=self.response_timeout_s,
                resend_after_wall_s=2.0 if self.idempotent else None,
                response_timeout_wall_s=self.response_timeout_wall_s)
        self._call = self._calls[self.shelf]
        super().initialise()

    def on_response(self, response: Any) -> Status:
        """SUCCESS and a ``shelf_scanned`` event when the server scanned it."""
        if not response.success:
            return self.fail(response.message)
        self.inspection.scanned.append(self.shelf)
        self.events.emit(SHELF_SCANNED, source=self, message=response.message,
                         shelf=self.shelf)
        return self.succeed(response.message, log=False)

    def shutdown(self) -> None:
        """Destroy every shelf's client."""
        for call in self._calls.values():
            call.destroy()
        self._calls.clear()
        self._call = None


def _processes(settings: MissionSettings) -> list[Process]:
    """The scan server, a program of this package, on the mission's clock.

    It serves the shelves :data:`SHELVES_FILE` names.
    """
    shelves = list(load_shelves(SHELVES_FILE))
    return [Process("scan", "", SCANNER, (),
                    {"use_sim_time": settings.use_sim_time, "shelves": shelves},
                    python_path=(str(Path(__file__).resolve().parents[1]),))]


def _check(_values: Any, _locations: Any, _file: str) -> list[str]:
    """The shelves' data, checked before the run starts (its errors name file and field)."""
    try:
        load_shelves(SHELVES_FILE)
    except ShelfDataError as err:
        return [str(err)]
    return []


def _start(_node: Any, _source: str, _locations: Mapping[str, Any]) -> AppRun:
    """A fresh inspection for the run; the status says how many shelves it scanned."""
    inspection = Inspection()
    return AppRun(context={"inspection": inspection},
                  status=lambda: {"shelves_scanned": len(inspection.scanned)})


def _status_text(document: Mapping[str, Any]) -> str:
    """``shelves scanned: 4`` in a status line (the studio's header, ``sar-tree watch``)."""
    count = document.get("shelves_scanned")
    return "" if count is None else f"shelves scanned: {count}"


def _progress(event: MissionEvent) -> str | None:
    """The console line of a scan."""
    return event.message if event.kind == SHELF_SCANNED else None


def _report(_inputs: Any, events: Sequence[MissionEvent],
            document: dict[str, Any]) -> dict[str, Any]:
    """``mission.json``'s ``shelves_scanned`` (with times) and ``waypoints_visited``.

    A waypoint is a goal reached, named by the shelf whose pose it was (``shelf A``), or
    by its node when it was no shelf's (``GoHome``).
    """
    from sar_framework.report import since_start

    origin = document.get("sim_start_s")
    scans = [{"shelf": e.value("shelf"), "sim_s": round(since_start(e.sim_s, origin), 2)}
             for e in events if e.kind == SHELF_SCANNED]
    if not scans:
        return {}
    reached: list[str] = []
    shelf = ""
    for event in events:
        if event.kind == SHELF_GOAL:
            shelf = event.value("shelf")
        elif event.kind in (EventKind.GOAL_REACHED, EventKind.GOAL_FAILED):
            if event.kind == EventKind.GOAL_REACHED:
                reached.append(f"shelf {shelf}" if shelf else event.node_name)
            shelf = ""
    return {"shelves_scanned": scans, "waypoints_visited": reached}


def _summary(document: Mapping[str, Any]) -> list[str]:
    """The summary's words: shelves scanned and waypoints visited."""
    if "shelves_scanned" not in document:
        return []
    shelves = [s["shelf"] for s in document["shelves_scanned"]]
    return [f"shelves scanned: {len(shelves)} ({', '.join(shelves)})",
            f"waypoints visited: {len(document['waypoints_visited'])}"]


APP = App(name="inspection_patrol", provides=("inspection",), check=_check, start=_start,
          processes=_processes, event_kinds={SHELF_SCANNED: "one shelf scanned",
                       SHELF_GOAL: "the next goal is a shelf's"},
          progress=_progress, report=_report, summary=_summary,
          marks={SHELF_SCANNED: "found"}, status_text=_status_text)
