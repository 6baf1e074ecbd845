"""A rosbag2-compatible MCAP file: profile ``ros2``, ``ros2msg`` schemas, ``cdr`` messages.

What rosbag2's MCAP storage plugin writes, and what Foxglove, ``ros2 bag`` and the
``rosbags`` / ``mcap-ros2-support`` readers open: one schema per message type (its name
``pkg/msg/Name`` as :func:`.msgdefs.schema_name` gives it, its data the full definition
text of :mod:`.msgdefs`), one channel per topic with the ROS type name in its metadata
(``ros_type``), each message the CDR bytes as received from the middleware. Plain Python
(no ROS).
"""

from __future__ import annotations

import time
from pathlib import Path
from typing import IO

from mcap.writer import CompressionType, Writer

from sar_framework.recording.msgdefs import message_definition, schema_name

PROFILE = "ros2"
SCHEMA_ENCODING = "ros2msg"
MESSAGE_ENCODING = "cdr"
LIBRARY = "sar_framework recorder"
#: The channel metadata key naming the ROS type of a topic (where the schema name differs).
ROS_TYPE_KEY = "ros_type"


class BagWriter:
    """Writes CDR messages of named topics into one MCAP file.

    Args:
        path: The file to create (its folder is created too).
    """

    def __init__(self, path: str | Path) -> None:
        self.path = Path(path)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self._stream: IO[bytes] = self.path.open("wb")
        self._writer = Writer(self._stream, compression=CompressionType.ZSTD)
        self._writer.start(profile=PROFILE, library=LIBRARY)
        self._schemas: dict[str, int] = {}
        self._channels: dict[str, int] = {}
        self._sequence: dict[str, int] = {}
        self.messages = 0
        self.closed = False

    def add_topic(self, topic: str, type_name: str, offered_qos: str = "") -> None:
        """Declare a topic and its type (before its first message).

        Args:
            topic: The topic name.
            type_name: Its full type name, e.g. ``tf2_msgs/msg/TFMessage``.
            offered_qos: rosbag2's ``offered_qos_profiles`` YAML text, if known.

        Raises:
            DefinitionError: The type's interface files are not installed.
        """
        if topic in self._channels:
            return
        if type_name not in self._schemas:
            definition = message_definition(type_name)
            self._schemas[type_name] = self._writer.register_schema(
                schema_name(type_name), SCHEMA_ENCODING, definition.encode("utf-8"))
        metadata = {"offered_qos_profiles": offered_qos} if offered_qos else {}
        metadata[ROS_TYPE_KEY] = type_name
        self._channels[topic] = self._writer.register_channel(
            topic, MESSAGE_ENCODING, self._schemas[type_name], metadata)
        self._sequence[topic] = 0

    def write(self, topic: str, data: bytes, log_time_ns: int | None = None) -> None:
        """Write one serialized message of a declared topic.

        Args:
            topic: The topic (declared with :meth:`add_topic`).
            data: The CDR bytes.
            log_time_ns: Receive time, nanoseconds since the epoch (now by default).
        """
        stamp = time.time_ns() if log_time_ns is None else log_time_ns
        self._sequence[topic] += 1
        self._writer.add_message(self._channels[topic], log_time=stamp, data=data,
                                 publish_time=stamp, sequence=self._sequence[topic])
        self.messages += 1

    def attach(self, name: str, data: bytes, media_type: str = "text/plain") -> None:
        """Store a file (the tree, the parameters) in the recording as an attachment."""
        now = time.time_ns()
        self._writer.add_attachment(create_time=now, log_time=now, name=name,
                                    media_type=media_type, data=data)

    def add_metadata(self, name: str, values: dict[str, str]) -> None:
        """Store a metadata record (string keys and values)."""
        self._writer.add_metadata(name, values)

    def close(self) -> None:
        """Write the summary and close the file (idempotent)."""
        if self.closed:
            return
        self.closed = True
        self._writer.finish()
        self._stream.close()
