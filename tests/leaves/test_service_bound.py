"""The service response bound, judged on a controlled clock and a controlled executor."""

from __future__ import annotations

from typing import Any

from sar_framework.leaves.service_call import PolledServiceCall


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


def started_call(node: FakeNode) -> PolledServiceCall:
    call = PolledServiceCall(node, object, "detect_survivor", server_timeout_s=10.0,
                             response_timeout_s=10.0, resend_after_wall_s=None)
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
