"""Around nav2_simple_commander's BasicNavigator: its wait in a thread, and what it waits for.

Used by :mod:`.nav2_startup`, which runs ``waitUntilNav2Active`` in a helper thread to
bound it.
"""

from __future__ import annotations

import threading
from typing import Any


def wait_quietly(nav: Any, navigator: str, localizer: str,
                 failure: list[BaseException]) -> None:
    """Run ``waitUntilNav2Active``; keep its error unless the context was shut down."""
    try:
        nav.waitUntilNav2Active(navigator=navigator, localizer=localizer)
    except Exception as err:
        if nav.context.ok():
            failure.append(err)


def join_after_shutdown(waiter: threading.Thread) -> None:
    """At exit: shut the context down (its executor then stops) and join the thread.

    A thread still inside rcl's wait when the interpreter finalises aborts the process
    ("terminate called without an active exception").
    """
    import rclpy

    rclpy.try_shutdown()
    waiter.join(timeout=2.0)


def stuck_step(nav: Any, localizer: str, navigator: str) -> str:
    """Name the step BasicNavigator is stuck in, worded as the rclpy path words it."""
    def served(name: str) -> bool:  # a server, not BasicNavigator's own client
        return nav.count_services(f"{name}/get_state") > 0  # in its namespace

    def service(name: str) -> str:  # its full name, in the robot's namespace
        return nav.resolve_service_name(f"{name}/get_state")

    if not served(localizer):
        return f"{localizer} never reported ACTIVE ({service(localizer)} never appeared)"
    if not getattr(nav, "initial_pose_received", False):
        return (f"{localizer} never answered /initialpose on /amcl_pose (or never became "
                "ACTIVE)")
    if not served(navigator):
        return f"{navigator} never reported ACTIVE ({service(navigator)} never appeared)"
    return f"{navigator} never reported ACTIVE"
