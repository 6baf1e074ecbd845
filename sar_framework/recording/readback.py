"""Read a mission recording back into the files the mission report is made from.

:func:`read_recording` decodes a recording (the ``mcap`` reader, and rclpy's own CDR
deserialiser with the installed message classes) into a :class:`Recording`: the tree's
status per tick, the runner's events, the robot's poses in ``map``, the navigation goals,
the map the robot drove on (``/map``), every service's calls (from its ``_service_event``
topic), and the tree and parameter files attached to it. :func:`write_report_inputs` turns it
into the files :mod:`sar_framework.report` reads (``events.jsonl``, ``status.json``,
``trace.jsonl``, the map as ``map.pgm`` and ``map.yaml`` named by the trace, and the apps'
files from their services' calls: :attr:`~sar_framework.app.App.replayed`), so a replayed
report is drawn by the same code as a live one, on the same map.
"""

from __future__ import annotations

import json
import math
import struct
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

from sar_framework.app.app import ServiceCall
from sar_framework.app.discovery import installed_apps
from sar_framework.events.event import EVENT_TOPIC, MissionEvent
from sar_framework.events.jsonl import EVENTS_FILE, EventFileWriter
from sar_framework.recording.bag_writer import ROS_TYPE_KEY
from sar_framework.recording.recorder import ATTACHMENT_PARAMS, METADATA_NAME, message_class
from sar_framework.runner.entry_values import apply_entries
from sar_framework.runner.tree_status import STATUS_TOPIC, StatusFormatError, decode_status
from sar_framework.sim.occupancy import OccupancyGrid

if TYPE_CHECKING:
    from sar_framework.app import App

GOAL_STATUS_TOPIC = "/navigate_to_pose/_action/status"
MAP_TOPIC = "/map"
SERVICE_EVENTS_SUFFIX = "/_service_event"
"""A service's introspection topic ends so (``/detect/_service_event``)."""
GLOBAL_FRAME = "map"
#: The robot's frame is the one whose name starts so (``base_link``, ``base_footprint``).
ROBOT_FRAME_PREFIX = "base"
DECODED_TOPICS = frozenset({STATUS_TOPIC, EVENT_TOPIC, "/tf", "/tf_static",
                            GOAL_STATUS_TOPIC, MAP_TOPIC})
"""The topics a replay needs (the others stay undecoded), with every service's events."""
_REQUEST_RECEIVED, _RESPONSE_SENT = 1, 2


class RecordingError(ValueError):
    """The file is not a mission recording this version can read."""


@dataclass
class Recording:
    """What a mission recording holds, decoded.

    Attributes:
        path: The file.
        statuses: The tree status documents, in order, each with ``wall_s`` added (seconds
            since the first message of the recording).
        events: The runner's events, in order (one this version does not know is left out).
        poses: ``(sim_s, x, y, yaw)`` of the robot in ``map``, from ``/tf``.
        goals: ``(sim_s, goal id hex)`` of each navigation goal, when first seen.
        service_calls: Service topic (``/report/_service_event``) -> its calls answered,
            in order.
        map: The last map latched on ``/map``, or None (a recording without one).
        attachments: Attachment name -> bytes (the tree files, plugin sources and
            parameter file).
        metadata: The recorder's metadata (original tree and parameter paths).
        wall_duration_s: Seconds from the first to the last message.
    """

    path: Path
    statuses: list[dict[str, Any]] = field(default_factory=list)
    events: list[MissionEvent] = field(default_factory=list)
    poses: list[tuple[float, float, float, float]] = field(default_factory=list)
    goals: list[tuple[float, str]] = field(default_factory=list)
    service_calls: dict[str, list[ServiceCall]] = field(default_factory=dict)
    map: OccupancyGrid | None = None
    attachments: dict[str, bytes] = field(default_factory=dict)
    metadata: dict[str, str] = field(default_factory=dict)
    wall_duration_s: float = 0.0


def _grid(msg: Any) -> OccupancyGrid:
    """A ``nav_msgs/msg/OccupancyGrid`` as the report's grid (row 0 the minimum y)."""
    import numpy as np

    info = msg.info
    data = np.asarray(msg.data, dtype=np.int8).reshape(info.height, info.width)
    return OccupancyGrid(data=data, resolution=float(info.resolution),
                         origin_x=float(info.origin.position.x),
                         origin_y=float(info.origin.position.y))


def _stamp_s(stamp: Any) -> float:
    return stamp.sec + stamp.nanosec / 1e9


def _yaw(rotation: Any) -> float:
    return math.atan2(2.0 * (rotation.w * rotation.z + rotation.x * rotation.y),
                      1.0 - 2.0 * (rotation.y * rotation.y + rotation.z * rotation.z))


class PoseTracker:
    """Composes the latest 2D transforms of ``/tf`` and ``/tf_static`` up to ``map``."""

    def __init__(self) -> None:
        self.parent: dict[str, tuple[str, float, float, float]] = {}

    def update(self, message: Any) -> list[tuple[float, float, float, float]]:
        """Take a ``tf2_msgs/TFMessage``; return the robot poses ``(stamp_s, x, y, yaw)``."""
        moved = []
        for transform in message.transforms:
            t = transform.transform
            self.parent[transform.child_frame_id] = (
                transform.header.frame_id, t.translation.x, t.translation.y, _yaw(t.rotation))
        for transform in message.transforms:
            if not transform.child_frame_id.startswith(ROBOT_FRAME_PREFIX):
                continue
            pose = self.in_global(transform.child_frame_id)
            if pose is not None:
                moved.append((_stamp_s(transform.header.stamp), *pose))
        return moved

    def in_global(self, frame: str) -> tuple[float, float, float] | None:
        """``frame``'s pose ``(x, y, yaw)`` in ``map``, or None while a link is missing."""
        x = y = yaw = 0.0
        for _ in range(len(self.parent) + 1):
            if frame == GLOBAL_FRAME:
                return x, y, yaw
            if frame not in self.parent:
                return None
            parent, px, py, pyaw = self.parent[frame]
            x, y = (px + math.cos(pyaw) * x - math.sin(pyaw) * y,
                    py + math.sin(pyaw) * x + math.cos(pyaw) * y)
            yaw += pyaw
            frame = parent
        return None


def read_recording(path: str | Path) -> Recording:
    """Decode a mission recording.

    Args:
        path: The ``.mcap`` file.

    Returns:
        The decoded recording.

    Raises:
        RecordingError: Not an MCAP file, or not readable.
    """
    from mcap.exceptions import McapError
    from mcap.reader import make_reader
    from rclpy.serialization import deserialize_message

    from sar_framework.runner.event_topic import from_message

    recording = Recording(Path(path))
    tracker = PoseTracker()
    classes: dict[str, Any] = {}
    requests: dict[tuple[str, bytes, int], Any] = {}
    seen_goals: set[str] = set()
    first_ns: int | None = None
    last_ns = 0
    try:
        with recording.path.open("rb") as stream:
            reader = make_reader(stream)
            for schema, channel, message in reader.iter_messages(log_time_order=True):
                if schema is None or (channel.topic not in DECODED_TOPICS and not
                                      channel.topic.endswith(SERVICE_EVENTS_SUFFIX)):
                    continue
                type_name = channel.metadata.get(ROS_TYPE_KEY, schema.name)
                if type_name not in classes:
                    classes[type_name] = message_class(type_name)
                msg = deserialize_message(message.data, classes[type_name])
                first_ns = message.log_time if first_ns is None else first_ns
                last_ns = max(last_ns, message.log_time)
                if channel.topic == STATUS_TOPIC:
                    try:
                        document = decode_status(msg.data)
                    except StatusFormatError:
                        continue
                    document["wall_s"] = round((message.log_time - first_ns) / 1e9, 3)
                    recording.statuses.append(document)
                elif channel.topic == EVENT_TOPIC:
                    try:
                        recording.events.append(from_message(msg))
                    except ValueError:
                        continue  # a kind a later version added
                elif channel.topic == MAP_TOPIC:
                    recording.map = _grid(msg)
                elif channel.topic in ("/tf", "/tf_static"):
                    recording.poses.extend(tracker.update(msg))
                elif channel.topic == GOAL_STATUS_TOPIC:
                    for status in msg.status_list:
                        goal = bytes(status.goal_info.goal_id.uuid).hex()
                        if goal not in seen_goals:
                            seen_goals.add(goal)
                            recording.goals.append((_stamp_s(status.goal_info.stamp), goal))
                elif channel.topic.endswith(SERVICE_EVENTS_SUFFIX):
                    key = (channel.topic, bytes(msg.info.client_gid), msg.info.sequence_number)
                    if msg.info.event_type == _REQUEST_RECEIVED and msg.request:
                        requests[key] = msg.request[0]
                    elif msg.info.event_type == _RESPONSE_SENT and msg.response and \
                            key in requests:
                        recording.service_calls.setdefault(channel.topic, []).append(
                            ServiceCall(requests.pop(key), msg.response[0],
                                        _stamp_s(msg.info.stamp)))
            recording.attachments = {a.name: a.data for a in reader.iter_attachments()}
            recording.metadata = next((dict(m.metadata) for m in reader.iter_metadata()
                                       if m.name == METADATA_NAME), {})
    except (McapError, OSError, ValueError, ImportError, struct.error) as err:
        raise RecordingError(f"{path}: cannot read the recording: "
                             f"{type(err).__name__}: {err}") from None
    recording.wall_duration_s = (last_ns - first_ns) / 1e9 if first_ns is not None else 0.0
    return recording


def status_document(recording: Recording) -> dict[str, Any]:
    """The runner's status file (``status.json``) rebuilt from the per-tick statuses.

    What happened (leaf verdicts, failures) is in the recorded events, not here.
    """
    statuses = recording.statuses
    nodes: dict[str, str] = {}
    entries: dict[str, dict[str, str]] = {}
    for document in statuses:
        for node in document["nodes"]:
            if node["status"] != "INVALID":
                nodes[node["uid"]] = node["status"]
        if "entries" in document:
            entries = apply_entries(entries, document["entries"],
                                    full=bool(document.get("entries_full")))
    end = statuses[-1] if statuses else {}
    running = [n["uid"] for n in end.get("nodes", []) if n["status"] == "RUNNING"]
    document = {
        "tree": recording.metadata.get("tree", ""), "status": end.get("status", "INVALID"),
        "ticks": end.get("tick", 0), "complete": bool(end.get("complete")),
        "wall_first_tick_s": statuses[0]["wall_s"] if statuses else None,
        "sim_start_s": statuses[0].get("sim_start_s", statuses[0]["sim_s"]) if statuses else None,
        "sim_end_s": end.get("sim_s"), "wall_duration_s": round(recording.wall_duration_s, 3),
        "nodes": nodes, "running": running,
    }
    if entries:
        document["entries"] = entries
    return document


def trace_records(recording: Recording, map_yaml: Path | None = None) -> list[dict[str, Any]]:
    """The simulator's trace (``trace.jsonl``) rebuilt from a recording.

    Robot poses with the distance travelled so far, and one ``accepted`` line per
    navigation goal; the ``start`` line names ``map_yaml``, the recorded map written out.
    """
    records: list[dict[str, Any]] = []
    path_m = 0.0
    previous: tuple[float, float] | None = None
    for sim_s, x, y, yaw in recording.poses:
        if previous is not None:
            path_m += math.hypot(x - previous[0], y - previous[1])
        if previous is None:
            records.append({"sim_s": sim_s, "event": "start", "x": x, "y": y, "yaw": yaw,
                            **({"map": str(map_yaml)} if map_yaml is not None else {})})
        elif (x, y) == previous:
            continue
        records.append({"sim_s": sim_s, "x": round(x, 4), "y": round(y, 4),
                        "yaw": round(yaw, 4), "path_m": round(path_m, 4)})
        previous = (x, y)
    records.extend({"sim_s": sim_s, "event": "accepted", "goal": index}
                   for index, (sim_s, _goal) in enumerate(recording.goals, 1))
    return records


def write_report_inputs(recording: Recording, folder: Path,
                        apps: Sequence[App] | None = None) -> dict[str, Path]:
    """Write the files :mod:`sar_framework.report` reads, from a recording.

    Args:
        recording: The decoded recording.
        folder: The report folder (created).
        apps: The apps whose files are rebuilt from their services' calls (the installed
            ones when None).

    Returns:
        ``{"params": ...}``: the attached parameter file, written into ``folder`` (none
        when the recording has no such attachment).
    """
    from sar_framework.sim.map_writer import write_map

    folder.mkdir(parents=True, exist_ok=True)
    map_yaml = write_map(recording.map, folder / "map")[1] if recording.map is not None else None
    (folder / "status.json").write_text(json.dumps(status_document(recording), indent=1),
                                        encoding="utf-8")
    (folder / "trace.jsonl").write_text(
        "".join(json.dumps(r) + "\n" for r in trace_records(recording, map_yaml)),
        encoding="utf-8")
    for app in installed_apps() if apps is None else apps:
        if app.replayed is not None:
            app.replayed(recording.service_calls, folder)
    events = EventFileWriter(folder / EVENTS_FILE)
    for event in recording.events:
        events(event)
    events.close()
    files: dict[str, Path] = {}
    if ATTACHMENT_PARAMS in recording.attachments:
        files["params"] = folder / ATTACHMENT_PARAMS
        files["params"].write_bytes(recording.attachments[ATTACHMENT_PARAMS])
    return files
