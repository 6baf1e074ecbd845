"""Ask lifecycle nodes whether they are ACTIVE, re-sending unanswered asks, never blocking.

The Nav2 start-up uses it twice: before BasicNavigator asks (on the runner's context, so
the discovery it waits for is the one BasicNavigator then uses), and when BasicNavigator's
own wait may be stuck on a lost reply (on a context of its own): an unanswered
``get_state`` is sent again (DDS can drop the reply to a request sent just after discovery).
"""

from __future__ import annotations

import time
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from rclpy.context import Context

#: ``lifecycle_msgs/msg/State.PRIMARY_STATE_ACTIVE``.
ACTIVE_STATE_ID = 3
#: Longest wait of one :meth:`LifecycleProbe.all_active`.
SPIN_STEP_S = 0.05


class LifecycleProbe:
    """Ask lifecycle nodes for their state, re-sending unanswered asks.

    Args:
        names: The lifecycle nodes (``amcl``, ``bt_navigator``).
        resend_s: Seconds after which an unanswered request is sent again.
        namespace: The robot's namespace the names are in (the runner's; ``/`` alone).
        context: The rclpy context to ask on; None: a context of its own, shut down by
            :meth:`close`.
    """

    def __init__(self, names: tuple[str, ...], *, resend_s: float = 1.0,
                 namespace: str = "/", context: Context | None = None) -> None:
        from lifecycle_msgs.srv import GetState
        from rclpy.context import Context
        from rclpy.executors import SingleThreadedExecutor
        from rclpy.node import Node

        self._own_context = context is None
        if context is None:
            context = Context()
            context.init()
        self._context = context
        self._node = Node("sar_nav2_probe", namespace=namespace, context=self._context)
        self._executor = SingleThreadedExecutor(context=self._context)
        self._executor.add_node(self._node)
        self._clients = {n: self._node.create_client(GetState, f"{n}/get_state")
                         for n in names}
        self._asks: dict[str, tuple[float, list[Any]]] = {}
        self._active: set[str] = set()
        self._states: dict[str, str] = {}  # the last state label each node answered
        self._resend_s = resend_s

    def all_active(self) -> bool:
        """Spin briefly, (re-)ask the nodes not yet seen ACTIVE; whether all are."""
        from lifecycle_msgs.srv import GetState

        self._executor.spin_once(timeout_sec=SPIN_STEP_S)
        now = time.monotonic()
        for name, client in self._clients.items():
            if name in self._active:
                continue
            sent, futures = self._asks.get(name, (0.0, []))
            answers = [f.result() for f in futures if f.done() and f.result() is not None]
            if answers:
                self._states[name] = answers[-1].current_state.label
            if any(a.current_state.id == ACTIVE_STATE_ID for a in answers):
                self._active.add(name)
            elif now - sent > self._resend_s and client.service_is_ready():
                self._asks[name] = (now, [*futures, client.call_async(GetState.Request())])
        return len(self._active) == len(self._clients)

    def served(self, name: str) -> bool:
        """Whether ``name``'s ``get_state`` service has been discovered."""
        return self._clients[name].service_is_ready()

    def not_active(self) -> list[str]:
        """The nodes not yet seen ACTIVE, in the order given."""
        return [name for name in self._clients if name not in self._active]

    def last_state(self, name: str) -> str:
        """The state ``name`` last answered (``inactive``...), or "" before any answer."""
        return self._states.get(name, "")

    def close(self) -> None:
        """Destroy the node (and shut the probe's own context down)."""
        self._executor.shutdown(timeout_sec=0.0)
        self._node.destroy_node()
        if self._own_context:
            self._context.try_shutdown()
