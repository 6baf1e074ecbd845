"""Test helpers for the embedded simulator: start it, set its run-time faults, reset it.

The same calls a user makes (``ros2 param set /sar_sim ...``, ``ros2 service call
/sar_sim/reset std_srvs/srv/Trigger``), from a test's rclpy node, so one running simulator
can serve many tests (DESIGN21's contract)::

    with sim_process(tmp_dir, speed=40.0) as sim, ros_node("t") as (node, executor):
        assert all(r.successful for r in set_sim_params(node, executor,
                                                         phantom_obstacles=["1:-0.5:0.3"]))
        ...
        assert reset_sim(node, executor).success
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

from sar_framework.testing.processes import NodeProcess
from sar_framework.testing.spin import call_service, spin_until


@contextmanager
def sim_process(log_dir: Path, *params: str, speed: float = 40.0) -> Iterator[NodeProcess]:
    """Run ``python -m sar_framework.sim`` until the block ends; yield once it is ready.

    Args:
        log_dir: Where its output goes.
        *params: ``name:=value`` parameter overrides.
        speed: The speed factor.
    """
    args = ["-m", "sar_framework.sim", "--ros-args", "-p", f"speed:={speed}"]
    for param in params:
        args += ["-p", param]
    with NodeProcess(args, "sim", log_dir=log_dir) as proc:
        proc.wait_for_output("ready", timeout=30)
        yield proc


def set_sim_params(node: Any, executor: Any, **values: Any) -> list[Any]:
    """SetParameters on ``/sar_sim`` (as ``ros2 param set``); the ``SetParametersResult``s."""
    from rcl_interfaces.srv import SetParameters
    from rclpy.parameter import Parameter

    request = SetParameters.Request()
    request.parameters = [Parameter(name, value=value).to_parameter_msg()
                          for name, value in values.items()]
    answer = call_service(node, executor, SetParameters, "/sar_sim/set_parameters", request)
    return list(answer.results)


def reset_sim(node: Any, executor: Any) -> Any:
    """Call ``/sar_sim/reset``; the ``Trigger`` response."""
    from std_srvs.srv import Trigger

    return call_service(node, executor, Trigger, "/sar_sim/reset", Trigger.Request(),
                        timeout=20.0)


def odometry_xy(node: Any, executor: Any, topic: str = "/odometry/filtered"
                ) -> tuple[float, float]:
    """The robot's odometry position, from the next messages on ``topic``."""
    from nav_msgs.msg import Odometry

    seen: list[Any] = []
    sub = node.create_subscription(Odometry, topic, seen.append, 10)
    try:
        assert spin_until(executor, lambda: len(seen) >= 2, 10.0), f"no {topic}"
        position = seen[-1].pose.pose.position
        return position.x, position.y
    finally:
        node.destroy_subscription(sub)
