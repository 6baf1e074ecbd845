"""ServiceLeaf against a real service; the topic leaves against a real topic."""

from __future__ import annotations

from typing import Any

from py_trees.common import Status

from sar_framework.engine.plugin import leaf
from sar_framework.leaves import (
    PublisherLeaf,
    ServiceLeaf,
    TopicCondition,
    service_params,
    topic_params,
)
from sar_framework.testing.ros_harness import tick_until_done
from sar_framework.testing.spin import spin_until

OUTER_S = 30.0  # outer safety bound on every wait


@leaf(params=[*service_params("toolkit_switch")])
class Switch(ServiceLeaf):
    """Turn a switch on; SUCCESS when the server says it did."""

    service_type = "std_srvs/srv/SetBool"

    def set_request(self, request: Any) -> None:
        request.data = True

    def on_response(self, response: Any) -> Status:
        if response.success:
            return self.succeed(response.message)
        return self.fail(f"refused: {response.message}")


@leaf(params=[*topic_params("toolkit_chatter", latched=True)])
class Say(PublisherLeaf):
    """Publish a greeting."""

    message_type = "std_msgs/msg/String"

    def set_message(self, message: Any) -> None:
        message.data = "hello"


@leaf(params=[*topic_params("toolkit_chatter", latched=True)], condition=True)
class Heard(TopicCondition):
    """Whether the newest message on the topic is a greeting."""

    message_type = "std_msgs/msg/String"

    def check(self, message: Any) -> bool:
        return message is not None and message.data == "hello"


def serve_switch(server: Any, name: str, *, success: bool) -> list[bool]:
    from std_srvs.srv import SetBool

    asked: list[bool] = []

    def answer(request: Any, response: Any) -> Any:
        asked.append(request.data)
        response.success, response.message = success, "switched" if success else "stuck"
        return response

    server.create_service(SetBool, name, answer)
    return asked


def switch(service_name: str, server_timeout_s: float = 10.0) -> Switch:
    return Switch(name="Switch", service_name=service_name, server_timeout_s=server_timeout_s,
                  response_timeout_s=10.0)


def test_a_service_leaf_sends_its_request_and_judges_the_answer(ros) -> None:
    _node, executor, server, trees = ros
    asked = serve_switch(server, "switch_ok", success=True)
    leaf = switch("switch_ok")
    assert tick_until_done(executor, trees(leaf), OUTER_S) == Status.SUCCESS
    assert asked[:1] == [True]
    assert leaf.feedback_message == "switched"


def test_a_refusal_fails_with_the_reason(ros) -> None:
    _node, executor, server, trees = ros
    serve_switch(server, "switch_stuck", success=False)
    leaf = switch("switch_stuck")
    assert tick_until_done(executor, trees(leaf), OUTER_S) == Status.FAILURE
    assert leaf.feedback_message == "refused: stuck"


def test_a_missing_service_fails_after_its_bound(ros) -> None:
    _node, executor, _server, trees = ros
    leaf = switch("no_such_switch", server_timeout_s=0.5)
    tree = trees(leaf)
    tree.tick()
    assert leaf.status == Status.RUNNING
    assert tick_until_done(executor, tree, OUTER_S) == Status.FAILURE
    assert leaf.feedback_message == "/no_such_switch service not available after 0.5 s"


def test_the_topic_condition_answers_on_the_newest_message(ros) -> None:
    _node, executor, _server, trees = ros
    heard = Heard(name="Heard", topic="chatter_t", qos_depth=1, qos_reliable=True,
                  qos_latched=True)
    say = Say(name="Say", topic="chatter_t", qos_depth=1, qos_reliable=True, qos_latched=True)
    heard_tree = trees(heard)
    heard_tree.tick()
    assert heard.status == Status.FAILURE
    assert heard.feedback_message == "no message yet on chatter_t"
    say_tree = trees(say)
    say_tree.tick()
    assert say.status == Status.SUCCESS
    assert spin_until(executor, lambda: heard.status == Status.SUCCESS, OUTER_S,
                      step=heard_tree.tick), f"the condition saw {heard.last_message}"


def test_the_qos_is_the_declaration(ros) -> None:
    from rclpy.qos import DurabilityPolicy, ReliabilityPolicy

    node, _executor, _server, trees = ros
    say = Say(name="Say", topic="qos_t", qos_depth=3, qos_reliable=False, qos_latched=True)
    trees(say)
    (info,) = node.get_publishers_info_by_topic("/qos_t")
    assert info.qos_profile.reliability == ReliabilityPolicy.BEST_EFFORT
    assert info.qos_profile.durability == DurabilityPolicy.TRANSIENT_LOCAL
    assert say._publisher.qos_profile.depth == 3  # the graph does not carry the depth
