"""The plugin tutorial's ROS leaves, on the leaf toolkit: an action, a service, a topic."""

from typing import Any

from py_trees.common import Status

from sar_framework.engine.plugin import Param, leaf
from sar_framework.leaves import (
    STATUS_SUCCEEDED,
    ActionLeaf,
    ServiceLeaf,
    TopicCondition,
    action_params,
    service_params,
    topic_params,
)


@leaf(params=[
    Param("start", int, default=3, minimum=0, description="Where to count down from."),
    Param("period", float, default=0.1, minimum=0.0, description="Seconds per step."),
    *action_params("countdown", result_timeout_s=30.0),
])
class AskCountdown(ActionLeaf):
    """Ask the countdown server to count down; SUCCESS when it reaches zero."""

    action_type = "tutorial_interfaces/action/Countdown"

    def set_goal(self, goal: Any) -> None:
        goal.start, goal.period = self.start, self.period

    def on_feedback(self, feedback: Any) -> None:
        if feedback is not None:
            self.feedback_message = f"{feedback.remaining} to go"

    def on_result(self, status: int, result: Any) -> Status:
        if status == STATUS_SUCCEEDED:
            return self.succeed(f"counted {result.steps} steps")
        return self.fail(f"countdown ended with status {status}: {result.message}")


@leaf(params=[*service_params("reset_counter")])
class ResetCounter(ServiceLeaf):
    """Call a std_srvs/Trigger service; SUCCESS when it reports success."""

    service_type = "std_srvs/srv/Trigger"

    def on_response(self, response: Any) -> Status:
        if response.success:
            return self.succeed(response.message)
        return self.fail(f"reset refused: {response.message}")


@leaf(params=[*topic_params("go", latched=True)], condition=True)
class HeardGo(TopicCondition):
    """SUCCESS once the newest message on the topic says "go"."""

    message_type = "std_msgs/msg/String"

    def check(self, message: Any) -> bool:
        return message is not None and message.data == "go"
