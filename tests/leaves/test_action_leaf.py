"""ActionLeaf against a real action server: goal, feedback, result, halts and bounds."""

from __future__ import annotations

import time
from typing import Any

import pytest
from py_trees.common import Status

from sar_framework.engine.plugin import Param, leaf
from sar_framework.leaves import STATUS_ABORTED, ActionLeaf, GoalFailure, action_params
from sar_framework.testing.ros_harness import tick_until_done
from sar_framework.testing.spin import spin_until

from .servers import WaitServerLog, serve_wait

OUTER_S = 30.0  # outer safety bound on every wait (the servers answer in well under 1 s)


@leaf(params=[Param("seconds", int, default=3), *action_params("toolkit_wait")])
class WaitFor(ActionLeaf):
    """Ask a Wait server to wait; keep what the hooks saw."""

    action_type = "nav2_msgs/action/Wait"

    def __init__(self, name: str, **declared: Any) -> None:
        super().__init__(name, **declared)
        self.feedback_seen: list[int] = []
        self.failures: list[GoalFailure] = []
        self.halted = 0

    def set_goal(self, goal: Any) -> bool:
        goal.time.sec = self.seconds
        if self.seconds < 0:
            self.feedback_message = "a negative wait"
            return False
        return True

    def on_feedback(self, feedback: Any) -> Status | None:
        if feedback is not None:
            self.feedback_seen.append(int(feedback.time_left.sec))
        return None

    def on_failure(self, failure: GoalFailure, reason: str) -> Status:
        self.failures.append(failure)
        return super().on_failure(failure, reason)

    def on_halted(self) -> None:
        self.halted += 1


def make_leaf(action_name: str, **values: Any) -> WaitFor:
    declared = {"seconds": 3, "action_name": action_name, "server_timeout_s": 10.0,
                "result_timeout_s": 60.0, **values}
    return WaitFor(name="WaitFor", **declared)


def tick_slowly(executor: Any, tree: Any, leaf: WaitFor) -> None:
    """Once the server is known, tick 300 ms apart (a loaded machine) until the leaf ends."""
    assert spin_until(executor, leaf._goals()._client.server_is_ready, OUTER_S)

    def slow_tick() -> None:
        time.sleep(0.3)
        tree.tick()

    tree.tick()
    assert leaf._goals().in_flight  # sent on the first tick
    assert spin_until(executor, lambda: leaf.status != Status.RUNNING, OUTER_S, step=slow_tick)


def test_the_goal_comes_from_set_goal_and_success_from_the_result(ros) -> None:
    _node, executor, server, trees = ros
    log = WaitServerLog()
    serve_wait(server, "wait_ok", log)
    leaf = make_leaf("wait_ok", seconds=4)
    assert tick_until_done(executor, trees(leaf), OUTER_S) == Status.SUCCESS
    assert log.goals == [4]
    assert leaf.feedback_seen == [2, 1]
    assert leaf.feedback_message == "wait_ok succeeded"


def test_an_aborted_goal_fails_with_the_servers_reason(ros) -> None:
    _node, executor, server, trees = ros
    serve_wait(server, "wait_abort", WaitServerLog(outcome="abort"))
    leaf = make_leaf("wait_abort")
    assert tick_until_done(executor, trees(leaf), OUTER_S) == Status.FAILURE
    assert leaf.feedback_message == "wait_abort aborted: blocked"
    assert leaf.result.error_code == 7


def test_a_refused_goal_fails_without_sending(ros) -> None:
    _node, executor, server, trees = ros
    log = WaitServerLog()
    serve_wait(server, "wait_refused", log)
    leaf = make_leaf("wait_refused", seconds=-1)
    assert tick_until_done(executor, trees(leaf), OUTER_S) == Status.FAILURE
    assert leaf.feedback_message == "a negative wait"
    assert log.goals == []


def test_a_missing_server_fails_after_its_bound_on_the_nodes_clock(ros) -> None:
    _node, executor, _server, trees = ros
    leaf = make_leaf("no_such_wait", server_timeout_s=0.5)
    tree = trees(leaf)
    tree.tick()
    assert leaf.status == Status.RUNNING
    assert leaf.feedback_message == "waiting for the no_such_wait action server"
    assert tick_until_done(executor, tree, OUTER_S) == Status.FAILURE
    assert leaf.failures == [GoalFailure.SERVER_UNREACHABLE]
    assert leaf.feedback_message == "no_such_wait server not available after 0.5 s"


def test_a_slow_acceptance_is_not_judged_by_the_server_bound(ros) -> None:
    """The server bound ends once the server is ready: a late acceptance or a slow tick
    (here both last longer than the whole bound) does not fail the goal."""
    _node, executor, server, trees = ros
    log = WaitServerLog(accept_delay_wall_s=0.6)
    serve_wait(server, "wait_slow", log)
    leaf = make_leaf("wait_slow", server_timeout_s=0.2)
    tick_slowly(executor, trees(leaf), leaf)  # ticks further apart than the server bound
    assert leaf.status == Status.SUCCESS, leaf.feedback_message
    assert leaf.failures == []


def test_a_goal_past_its_result_bound_is_cancelled_and_fails(ros) -> None:
    _node, executor, server, trees = ros
    log = WaitServerLog(outcome="hang")
    serve_wait(server, "wait_hang", log)
    leaf = make_leaf("wait_hang", result_timeout_s=0.5)
    assert tick_until_done(executor, trees(leaf), OUTER_S) == Status.FAILURE
    assert leaf.failures == [GoalFailure.RESULT_TIMEOUT]
    assert leaf.feedback_message == "wait_hang goal not finished within 0.5 s; goal cancelled"
    assert spin_until(executor, lambda: log.cancels == 1, OUTER_S), "no cancel request"


def test_a_halt_cancels_the_goal_in_flight(ros) -> None:
    _node, executor, server, trees = ros
    log = WaitServerLog(outcome="hang")
    serve_wait(server, "wait_halt", log)
    leaf = make_leaf("wait_halt")
    tree = trees(leaf)
    tree.tick()
    assert spin_until(executor, lambda: leaf._goals().accepted, OUTER_S, step=tree.tick)
    leaf.stop(Status.INVALID)
    assert leaf.halted == 1
    assert leaf.feedback_message == "halted; wait_halt goal cancelled"
    assert spin_until(executor, lambda: log.cancels == 1, OUTER_S), "no cancel request"


def test_a_halt_before_the_acceptance_arrives_still_cancels_the_goal(ros) -> None:
    _node, executor, server, trees = ros
    log = WaitServerLog(outcome="hang", accept_delay_wall_s=0.5)
    serve_wait(server, "wait_early_halt", log)
    leaf = make_leaf("wait_early_halt")
    tree = trees(leaf)
    assert spin_until(executor, lambda: leaf._goals().in_flight, OUTER_S, step=tree.tick)
    assert not leaf._goals().accepted
    leaf.stop(Status.INVALID)
    assert leaf.halted == 1
    assert spin_until(executor, lambda: log.cancels == 1, OUTER_S), (
        f"the goal accepted after the halt was not cancelled (goals {log.goals})")


def test_the_result_code_reaches_on_result(ros) -> None:
    _node, executor, server, trees = ros
    serve_wait(server, "wait_codes", WaitServerLog(outcome="abort"))
    seen: list[int] = []

    class Lenient(WaitFor):
        def on_result(self, status: int, result: Any) -> Status:
            seen.append(status)
            return self.succeed("aborted, and that is fine")

    leaf = Lenient(name="Lenient", seconds=1, action_name="wait_codes",
                   server_timeout_s=10.0, result_timeout_s=60.0)
    assert tick_until_done(executor, trees(leaf), OUTER_S) == Status.SUCCESS
    assert seen == [STATUS_ABORTED]


def test_the_acceptance_bound_is_not_judged_on_one_slow_tick_alone(ros) -> None:
    """Nav2's ``server_timeout`` (here 50 ms of wall time for the acceptance): a tick that
    comes after the bound passed, before the executor took the acceptance in, gives the
    executor its turn instead of failing; the tick after the acceptance was taken in goes on.

    The order is made, not hoped for: no spin between the goal and the late tick (whatever
    the machine's load, the acceptance cannot have been taken in), then a spin until it is.
    """
    _node, executor, server, trees = ros
    serve_wait(server, "wait_ack", WaitServerLog())
    leaf = make_leaf("wait_ack")
    leaf.ack_timeout_wall_s = 0.05
    tree = trees(leaf)
    goals = leaf._goals()
    assert spin_until(executor, goals._client.server_is_ready, OUTER_S)
    tree.tick()
    assert goals.in_flight and not goals.accepted  # sent on the first tick
    time.sleep(0.1)  # past the 50 ms bound (a loaded machine only sleeps longer)
    tree.tick()
    assert leaf.status == Status.RUNNING, leaf.feedback_message
    assert spin_until(executor, goals._send_future.done, OUTER_S), (
        "the server's acceptance never reached the client")
    assert tick_until_done(executor, tree, OUTER_S) == Status.SUCCESS, leaf.feedback_message


@pytest.mark.parametrize(("resends", "sent"), [(0, ""), (1, " (sent 2 times)")])
def test_a_goal_never_accepted_fails_after_the_acceptance_bound(ros, resends: int,
                                                                sent: str) -> None:
    """With ``ack_resends``, the same goal is sent again before the leaf fails; every late
    acceptance is cancelled."""
    _node, executor, server, trees = ros
    log = WaitServerLog(accept_delay_wall_s=3.0, outcome="hang")
    serve_wait(server, f"wait_no_ack_{resends}", log)
    leaf = make_leaf(f"wait_no_ack_{resends}")
    leaf.ack_timeout_wall_s = 0.05
    leaf.ack_resends = resends
    assert tick_until_done(executor, trees(leaf), OUTER_S) == Status.FAILURE
    assert leaf.failures == [GoalFailure.SEND_GOAL_TIMEOUT]
    assert leaf.feedback_message == (
        f"wait_no_ack_{resends} did not accept the goal within 0.05 s{sent}")
    goals = [3] * (resends + 1)
    assert spin_until(executor, lambda: log.goals == goals and log.cancels == len(goals),
                      OUTER_S), (
        f"awaited {len(goals)} goal(s) received and every late acceptance cancelled; saw "
        f"goals {log.goals}, {log.cancels} cancel(s)")
