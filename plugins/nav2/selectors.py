"""Nav2's ControllerSelector and PlannerSelector: an id chosen on a topic, or a default.

Each subscribes to ``topic_name`` (``std_msgs/String``, reliable, transient local, depth 1,
as Nav2) and writes the last id received, else ``default_...``, to its output; with
neither it fails, as Nav2's do.
"""

from __future__ import annotations

from typing import Any

from py_trees.common import Status

from sar_framework.engine.plugin import leaf
from sar_framework.engine.ports import InputPort, OutputPort
from sar_framework.leaves import RosLeaf

from ._common import optional_input


class _Selector(RosLeaf):
    """Base of the selectors.

    Args:
        name: The behaviour's name.
        ports: ``topic_name``, the default and the selected id.
    """

    WHAT = ""
    TOPIC = ""

    def __init__(self, name: str, *, ports: Any) -> None:
        super().__init__(name)
        self.ports = ports
        self.last_selected = ""
        self._subscription: Any = None

    def setup(self, **kwargs: Any) -> None:
        """Take the node and subscribe to ``topic_name``."""
        super().setup(**kwargs)
        from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
        from std_msgs.msg import String

        qos = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                         durability=DurabilityPolicy.TRANSIENT_LOCAL)
        topic = optional_input(self.ports, "topic_name", self.TOPIC) or self.TOPIC
        self._subscription = self.node.create_subscription(String, topic, self.on_message, qos)

    def on_message(self, message: Any) -> None:
        """Remember the id a message selects."""
        self.last_selected = message.data

    def update(self) -> Status:
        """Write the selected id (or the default) and succeed; fail with neither."""
        if not self.last_selected:
            default = optional_input(self.ports, f"default_{self.WHAT}", "") or ""
            if not default:
                self.feedback_message = f"no {self.WHAT} selected and no default_{self.WHAT}"
                return Status.FAILURE
            self.last_selected = default
        self.ports.set(f"selected_{self.WHAT}", self.last_selected)
        self.feedback_message = f"{self.WHAT}: {self.last_selected}"
        return Status.SUCCESS

    def shutdown(self) -> None:
        """Destroy the subscription."""
        if self._subscription is not None:
            self.node.destroy_subscription(self._subscription)
            self._subscription = None


@leaf(ports=[
    InputPort("topic_name", str, default="controller_selector",
              description="The name of the topic used to received select command messages."),
    InputPort("default_controller", str, optional=True, description="The default value for "
              "the selected Controller if no message is received from the input topic."),
    OutputPort("selected_controller", str, description="The output selected Controller id."),
])
class ControllerSelector(_Selector):
    """Nav2's ControllerSelector: the controller id to give FollowPath's ``controller_id``."""

    WHAT = "controller"
    TOPIC = "controller_selector"


@leaf(ports=[
    InputPort("topic_name", str, default="planner_selector",
              description="The name of the topic used to received select command messages."),
    InputPort("default_planner", str, optional=True, description="The default value for the "
              "selected planner if no message is received from the input topic."),
    OutputPort("selected_planner", str, description="The output selected planner id."),
])
class PlannerSelector(_Selector):
    """Nav2's PlannerSelector: the planner id to give ComputePathToPose's ``planner_id``."""

    WHAT = "planner"
    TOPIC = "planner_selector"
