"""The service response bound, judged on a controlled clock and a controlled executor.

A call that may be resent is failed by its ROS-time bound only once its first resend had a poll
to be answered: at a high speed the bound is a fraction of a wall second.
"""

from __future__ import annotations

import threading
import time
from typing import Any

from py_trees.common import Status

from sar_framework.leaves.service_call import CallResult, PolledServiceCall
from sar_framework.testing.ros_harness import tick_until_done

from .test_service_and_topics import Switch

OUTER_S = 30.0  # outer safety bound on every wait (a resend comes after 0.05 s or 2 s)


class FakeFuture:
    """An rclpy future whose answer the test delivers (the executor's turn)."""

    def __init__(self) -> None:
        self.answer: Any = None
        self.cancelled = False

    def done(self) -> bool:
        return self.answer is not None

    def exception(self) -> None:
        return None

    def result(self) -> Any:
        return self.answer

    def cancel(self) -> None:
        self.cancelled = True


class FakeClient:
    service_name = "/robot3/detect_survivor"

    def __init__(self) -> None:
        self.sent: list[FakeFuture] = []

    def service_is_ready(self) -> bool:
        return True

    def call_async(self, _request: Any) -> FakeFuture:
        self.sent.append(FakeFuture())
        return self.sent[-1]

    def remove_pending_request(self, _future: FakeFuture) -> None:
        pass


class FakeTime:
    def __init__(self, clock: FakeClock) -> None:
        self.nanoseconds = int(clock.seconds * 1e9)


class FakeClock:
    def __init__(self) -> None:
        self.seconds = 0.0

    def now(self) -> FakeTime:
        return FakeTime(self)


class FakeNode:
    def __init__(self) -> None:
        self.client = FakeClient()
        self.clock = FakeClock()

    def create_client(self, _srv_type: Any, _name: str) -> FakeClient:
        return self.client

    def get_clock(self) -> FakeClock:
        return self.clock


def started_call(node: FakeNode, resend_after_wall_s: float | None = None) -> PolledServiceCall:
    call = PolledServiceCall(node, object, "detect_survivor", server_timeout_s=10.0,
                             response_timeout_s=10.0, resend_after_wall_s=resend_after_wall_s)
    call.start()
    assert call.poll(lambda: "request") is None
    assert len(node.client.sent) == 1
    return call


def test_one_slow_tick_does_not_fail_an_answer_waiting_for_the_executor() -> None:
    """The server answered within the bound, but the next tick comes 11 s (ROS time) after the
    request, before the executor took the answer in. That tick gives the executor its turn; the
    tick after it sees the answer."""
    node = FakeNode()
    call = started_call(node)
    node.clock.seconds = 11.0
    assert call.poll(lambda: "request") is None
    node.client.sent[0].answer = "found"  # the executor's turn
    node.clock.seconds = 11.1
    result = call.poll(lambda: "request")
    assert result is not None and result.error is None, result
    assert result.response == "found"


def test_an_answer_still_missing_at_the_tick_after_fails_naming_the_bound() -> None:
    """A call never resent fails at the second poll that sees its bound passed, as always."""
    node = FakeNode()
    call = started_call(node)
    node.clock.seconds = 11.0
    assert call.poll(lambda: "request") is None
    node.clock.seconds = 11.1
    result = call.poll(lambda: "request")
    assert result is not None
    assert result.error == "no response from /robot3/detect_survivor within 10.0 s"
    assert node.client.sent[0].cancelled


def test_a_new_request_is_judged_afresh() -> None:
    """A sighting of the bound passed belongs to one request: the next one gets its own grace."""
    node = FakeNode()
    call = started_call(node)
    node.clock.seconds = 11.0
    assert call.poll(lambda: "request") is None
    node.client.sent[0].answer = "found"
    assert call.poll(lambda: "request").response == "found"
    call.start()
    assert call.poll(lambda: "request") is None
    node.clock.seconds = 22.0
    assert call.poll(lambda: "request") is None
    node.client.sent[1].answer = "again"
    assert call.poll(lambda: "request").response == "again"


def poll_until_resent(node: FakeNode, call: PolledServiceCall) -> None:
    """Poll (every result None) until the call has sent its first resend."""
    deadline = time.monotonic() + OUTER_S
    while len(node.client.sent) < 2 and time.monotonic() < deadline:  # outer safety bound
        result = call.poll(lambda: "request")
        assert result is None, f"the call ended before its resend: {result}"
        time.sleep(0.01)
    assert len(node.client.sent) == 2, f"no resend within {OUTER_S} s (outer safety bound)"


def late_call(resend_after_wall_s: float) -> tuple[FakeNode, PolledServiceCall]:
    """A resendable call whose 10 s bound had passed at two polls, before any resend."""
    node = FakeNode()
    call = started_call(node, resend_after_wall_s)
    node.clock.seconds = 11.0
    assert call.poll(lambda: "request") is None
    node.clock.seconds = 11.1
    assert call.poll(lambda: "request") is None  # not failed: the resend has not been sent
    return node, call


def test_a_resendable_call_is_not_failed_before_its_resend_and_a_slow_answer_counts() -> None:
    """At 20x a 10 s bound is half a wall second: a just-started server answers after it."""
    node, call = late_call(resend_after_wall_s=600.0)  # no resend during this test
    node.clock.seconds = 30.0
    assert call.poll(lambda: "request") is None
    node.client.sent[0].answer = "scanned"
    result = call.poll(lambda: "request")
    assert result == CallResult(response="scanned")
    assert len(node.client.sent) == 1


def test_a_late_resendable_call_is_answered_by_its_resend() -> None:
    """The reply to the first request was lost; the server answers the resend."""
    node, call = late_call(resend_after_wall_s=0.05)
    poll_until_resent(node, call)
    node.client.sent[1].answer = "scanned"
    result = call.poll(lambda: "request")
    assert result == CallResult(response="scanned")
    assert node.client.sent[0].cancelled  # the lost one's answer, if it comes, is dropped


def test_a_late_call_fails_naming_the_bound_once_its_resend_had_a_poll() -> None:
    node, call = late_call(resend_after_wall_s=0.05)
    poll_until_resent(node, call)
    result = call.poll(lambda: "request")
    assert result == CallResult(error="no response from /robot3/detect_survivor within 10.0 s")
    assert [future.cancelled for future in node.client.sent] == [True, True]


def serve_switch_answering_the_resend(server: Any, name: str) -> list[bool]:
    """A SetBool server that answers a request only once a second one has come."""
    from rclpy.callback_groups import ReentrantCallbackGroup
    from std_srvs.srv import SetBool

    asked: list[bool] = []
    resent = threading.Event()

    def answer(request: Any, response: Any) -> Any:
        asked.append(request.data)
        if len(asked) > 1:
            resent.set()
        resent.wait(OUTER_S)  # outer safety bound
        response.success, response.message = True, "switched"
        return response

    server.create_service(SetBool, name, answer, callback_group=ReentrantCallbackGroup())
    return asked


def test_a_real_service_leaf_outlives_its_bound_until_its_resend_is_answered(ros) -> None:
    """A bound of 0.05 s (ROS time: the wall here) passes long before the 2 s resend."""
    _node, executor, server, trees = ros
    asked = serve_switch_answering_the_resend(server, "switch_resent")
    leaf = Switch(name="Switch", service_name="switch_resent", server_timeout_s=10.0,
                  response_timeout_s=0.05)
    assert tick_until_done(executor, trees(leaf), OUTER_S) == Status.SUCCESS, (
        leaf.feedback_message)
    assert leaf.feedback_message == "switched"
    assert asked[:2] == [True, True]
