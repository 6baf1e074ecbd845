"""``python -m sar_framework.recording``: record a mission into a rosbag2-compatible MCAP file.

::

    python -m sar_framework.recording --ros-args -p output:=mission.mcap \
        -p tree:=trees/search_and_rescue.yaml -p params_file:=config/mission_params.yaml \
        [-p plugin_path:=DIR_OR_FILE[:...]]

Subscribes to :data:`RECORDED_TOPICS` with ``raw=True`` (the CDR bytes as the middleware
delivered them, never deserialised) and writes each message as it arrives; the tree files
(the main one and its includes), the local plugin sources (:mod:`.sources`) and the
parameter file go into the recording as attachments, so ``sar-tree replay`` needs nothing
else. SIGINT or SIGTERM close the file (summary and index written).

An app's services publish their requests and answers as ROS 2 service introspection
events (``/<service>/_service_event``; :mod:`.introspection`); the app names those topics
(its ``recorded_topics``) and the recorder keeps them beside its own.
"""

from __future__ import annotations

import importlib
import os
import sys
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from sar_framework.events.event import EVENT_TOPIC, EVENT_TYPE
from sar_framework.recording.bag_writer import BagWriter
from sar_framework.recording.sources import RunSources, collect, media_type
from sar_framework.ros.teardown import bounded_teardown
from sar_framework.runner.tree_status import STATUS_TOPIC, STATUS_TYPE

if TYPE_CHECKING:
    from rclpy.node import Node

NODE_NAME = "sar_recorder"
ATTACHMENT_PARAMS = "mission_params.yaml"
METADATA_NAME = "sar_framework"
#: Messages each subscription holds while the recorder is busy: the middleware takes them
#: in on its own threads, so a burst (a fast simulator on a busy machine) is not lost.
QUEUE_DEPTH = 2000
#: Longest wait for a message before the stop flag is checked again.
SPIN_TIMEOUT_S = 0.1
#: Longest time spent, after a stop signal, writing the messages still queued.
DRAIN_S = 0.8
#: Longest wait for the recorder to start before the mission starts anyway.
STARTUP_TIMEOUT_S = 15.0


@dataclass(frozen=True)
class RecordedTopic:
    """One topic the recorder subscribes to.

    Attributes:
        name: The topic.
        type_name: Its full type name.
        latched: Published RELIABLE + TRANSIENT_LOCAL (subscribe so, to get the past).
    """

    name: str
    type_name: str
    latched: bool = False


RECORDED_TOPICS = (
    RecordedTopic("/tf", "tf2_msgs/msg/TFMessage"),
    RecordedTopic("/tf_static", "tf2_msgs/msg/TFMessage", latched=True),
    RecordedTopic("/amcl_pose", "geometry_msgs/msg/PoseWithCovarianceStamped", latched=True),
    RecordedTopic("/map", "nav_msgs/msg/OccupancyGrid", latched=True),
    RecordedTopic("/navigate_to_pose/_action/status", "action_msgs/msg/GoalStatusArray",
                  latched=True),
    RecordedTopic("/navigate_to_pose/_action/feedback",
                  "nav2_msgs/action/NavigateToPose_FeedbackMessage"),
    RecordedTopic(STATUS_TOPIC, STATUS_TYPE, latched=True),
    RecordedTopic(EVENT_TOPIC, EVENT_TYPE, latched=True),
)
"""What a mission recording holds (a topic nobody publishes simply stays empty). Odometry is
left out: ``/tf`` carries the same pose, and every extra stream costs the recorder time.
The apps' topics (their ``recorded_topics``) come beside them: :func:`app_topics`."""


def app_topics(entries: Sequence[str]) -> list[RecordedTopic]:
    """The recorder's ``app_topics`` parameter (``"NAME TYPE"`` each) as topics to record."""
    return [RecordedTopic(*entry.split()) for entry in entries if len(entry.split()) == 2]

_INFINITE = "{sec: 9223372036, nsec: 854775807}"


def offered_qos_yaml(latched: bool) -> str:
    """rosbag2's ``offered_qos_profiles`` text for a RELIABLE, depth 100 publisher.

    Args:
        latched: TRANSIENT_LOCAL (else VOLATILE) durability.
    """
    return (f"- history: keep_last\n  depth: 100\n  reliability: reliable\n"
            f"  durability: {'transient_local' if latched else 'volatile'}\n"
            f"  deadline: {_INFINITE}\n  lifespan: {_INFINITE}\n  liveliness: automatic\n"
            f"  liveliness_lease_duration: {_INFINITE}\n"
            "  avoid_ros_namespace_conventions: false\n")


def message_class(type_name: str) -> Any:
    """The Python class of a full type name (``pkg/srv/Name_Event`` and action parts too).

    Args:
        type_name: For example ``nav2_msgs/action/NavigateToPose_FeedbackMessage``.

    Raises:
        ImportError: The interface package is not installed.
    """
    package, kind, name = type_name.split("/")
    module = importlib.import_module(f"{package}.{kind}")
    if kind == "action" and name.endswith("_FeedbackMessage"):
        return getattr(module, name[: -len("_FeedbackMessage")]).Impl.FeedbackMessage
    return getattr(module, name)


class MissionRecorder:
    """Subscribes to the mission's topics on ``node`` and writes them into ``writer``.

    Args:
        node: The recorder's node.
        writer: The open MCAP file.
        topics: What to record.
    """

    def __init__(self, node: Node, writer: BagWriter,
                 topics: Sequence[RecordedTopic] = RECORDED_TOPICS) -> None:
        from sar_framework.ros.qos import latched_qos

        self.writer = writer
        self.node = node
        for topic in topics:
            try:
                cls = message_class(topic.type_name)
            except (ImportError, AttributeError) as err:
                node.get_logger().warning(f"not recording {topic.name}: {err}")
                continue
            writer.add_topic(topic.name, topic.type_name, offered_qos_yaml(topic.latched))
            qos = latched_qos(QUEUE_DEPTH) if topic.latched else QUEUE_DEPTH
            node.create_subscription(cls, topic.name, self._writer_for(topic.name), qos,
                                     raw=True)

    def _writer_for(self, topic: str) -> Any:
        def write(data: bytes) -> None:
            self.writer.write(topic, data)
        return write


def wait_until_recording(path: Path, alive: Callable[[], bool],
                         timeout_s: float = STARTUP_TIMEOUT_S) -> bool:
    """Wait until a starting recorder has created its file (its subscriptions come next).

    ``sar-tree run`` starts the mission's other processes only then, so a fast mission on
    a busy machine does not begin before the recorder listens.

    Args:
        path: The recording (removed beforehand by the caller).
        alive: Returns whether the recorder process still runs.
        timeout_s: Upper bound of the wait.

    Returns:
        Whether the file appeared.
    """
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline and alive():
        if path.exists():
            return True
        time.sleep(0.02)
    return path.exists()


def drain(executor: Any, writer: BagWriter) -> None:
    """Write what is still queued (a busy recorder lags behind), for at most :data:`DRAIN_S`."""
    deadline = time.monotonic() + DRAIN_S
    while time.monotonic() < deadline:
        before = writer.messages
        executor.spin_once(timeout_sec=0.0)
        if writer.messages == before:
            executor.spin_once(timeout_sec=0.0)
            if writer.messages == before:
                return


def attach_run_files(writer: BagWriter, tree: str, params_file: str,
                     plugin_paths: Sequence[str]) -> None:
    """Attach the tree files, local plugin sources and parameter file, with their metadata.

    Args:
        writer: The open recording.
        tree: The main tree file.
        params_file: The mission parameter file ("" for none).
        plugin_paths: The run's extra plugin paths (relative to the working folder).
    """
    run_files = collect(tree, plugin_paths) if tree else RunSources()
    for name, path in run_files.attachments.items():
        writer.attach(name, path.read_bytes(), media_type(path))
    if params_file and Path(params_file).is_file():
        writer.attach(ATTACHMENT_PARAMS, Path(params_file).read_bytes(), "application/yaml")
    writer.add_metadata(METADATA_NAME, {"tree": tree, "params_file": params_file,
                                        **run_files.metadata})


def run(argv: Sequence[str] | None = None) -> int:
    """Record until SIGINT/SIGTERM; return the exit code.

    0 after a signal, 2 when ``output`` is missing or cannot be written, or a parameter
    breaks its rule (:data:`~sar_framework.recording.params.RECORDER_PARAMETERS`).

    Args:
        argv: The command line (``sys.argv`` when None), ROS arguments included.
    """
    import rclpy
    from rclpy.experimental import EventsExecutor
    from rclpy.node import Node
    from rclpy.signals import SignalHandlerOptions

    from sar_framework.mission.params_file import ParamsError
    from sar_framework.recording.params import RECORDER_PARAMETERS
    from sar_framework.ros.parameters import declare_table
    from sar_framework.stop_signals import stop_on_signals

    # Our own handlers: the context stays valid while the file is closed after a signal.
    rclpy.init(args=list(sys.argv if argv is None else argv),
               signal_handler_options=SignalHandlerOptions.NO)
    stop = stop_on_signals()
    node = Node(NODE_NAME)
    writer: BagWriter | None = None
    try:
        try:
            values = declare_table(node, RECORDER_PARAMETERS)
        except ParamsError as err:
            node.get_logger().error(str(err))
            return 2
        output, tree, params_file = values["output"], values["tree"], values["params_file"]
        plugin_path = values["plugin_path"]
        plugin_paths = (plugin_path.split(os.pathsep) if isinstance(plugin_path, str)
                        else list(plugin_path))
        if not output:
            node.get_logger().error("parameter 'output' (the .mcap file to write) is not set")
            return 2
        try:
            writer = BagWriter(output)
        except OSError as err:
            node.get_logger().error(f"cannot write the recording '{output}': {err.strerror}")
            return 2
        attach_run_files(writer, tree, params_file, plugin_paths)
        topics = (*RECORDED_TOPICS, *app_topics(values["app_topics"] or ()))
        MissionRecorder(node, writer, topics)
        node.get_logger().info(f"recording {len(topics)} topics into {output}")
        executor = EventsExecutor()  # as the runner's: /tf at the simulator's update rate
        executor.add_node(node)
        while not stop:
            executor.spin_once(timeout_sec=SPIN_TIMEOUT_S)
        drain(executor, writer)
        executor.shutdown(timeout_sec=0.0)
    finally:
        if writer is not None:
            writer.close()
            node.get_logger().info(f"wrote {writer.messages} messages to {writer.path}")
        with bounded_teardown():  # Fast DDS's participant teardown can hang
            node.destroy_node()
        rclpy.try_shutdown()
    return 0


def main(argv: Sequence[str] | None = None) -> None:
    """Console entry point."""
    sys.exit(run(argv))
