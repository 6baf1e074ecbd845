"""The robot's pose from TF, as Nav2's ``nav2_util::getCurrentPose`` gives it.

One ``tf2_ros.Buffer`` and ``TransformListener`` per ROS node, made on first use and
shared by every leaf set up on that node (Nav2 shares one ``tf_buffer`` the same way).

As Nav2's C++ listener does by default, the listener spins in a thread of its own, so
/tf reaches the buffer while the leaf's executor is busy; otherwise, under load, the
messages wait in that executor's queue and the pose a leaf reads is stale. tf2_ros's
``spin_thread=True`` would move the leaf's node itself to the thread's executor (a node
belongs to one executor) and spin it on the default context, so the listener gets a
private node on the leaf's context and its own executor here. The thread ends, and the
private node is destroyed, when the leaf's node is destroyed or its context shuts down.
"""

from __future__ import annotations

import itertools
import threading
from typing import Any

POLL_S = 0.1
"""How often the listener's thread looks whether the leaf's node is still alive (s)."""

_serial = itertools.count()
_listeners: dict[int, _Listener] = {}
_lock = threading.Lock()


class _Listener:
    """A ``Buffer`` fed by a ``TransformListener`` on a private node spun by its own thread.

    Args:
        owner: The leaf's node: the listener lives as long as it does.
    """

    def __init__(self, owner: Any) -> None:
        import rclpy
        from rclpy.executors import SingleThreadedExecutor
        from tf2_ros import Buffer, TransformListener

        self.owner = owner
        context = owner.context
        self.buffer = Buffer()
        self._node = rclpy.create_node(
            f"{owner.get_name()}_tf_listener_{next(_serial)}",
            namespace=owner.get_namespace(), context=context)
        self._listener = TransformListener(self.buffer, self._node)
        self._executor = SingleThreadedExecutor(context=context)
        self._executor.add_node(self._node)
        self._closed = threading.Event()
        self._thread = threading.Thread(
            target=self._spin, name=f"tf_listener:{owner.get_name()}", daemon=True)
        self._thread.start()
        # Only a flag: the context's shutdown holds the lock its ok() needs, so no join here.
        context.on_shutdown(self._closed.set)

    def owner_alive(self) -> bool:
        """Whether the leaf's node is still usable (not destroyed)."""
        try:
            self.owner.get_name()
        except Exception:  # rclpy's InvalidHandle once destroy_node was called
            return False
        return True

    def _spin(self) -> None:
        try:
            while not self._closed.is_set() and self.owner_alive():
                self._executor.spin_once(timeout_sec=POLL_S)
        except Exception:  # the context shut down under the spin
            pass
        finally:
            self._release()

    def _release(self) -> None:
        with _lock:
            if _listeners.get(id(self.owner)) is self:
                del _listeners[id(self.owner)]
        self._executor.shutdown()
        self._node.destroy_node()


def tf_buffer(node: Any) -> Any:
    """The node's shared ``tf2_ros.Buffer``, fed by its listener."""
    with _lock:
        held = _listeners.get(id(node))
        if held is None or held.owner is not node or held._closed.is_set():
            held = _listeners[id(node)] = _Listener(node)
        return held.buffer


def listener_threads() -> list[threading.Thread]:
    """The TF listeners' threads still running (to check that none outlives its node)."""
    return [thread for thread in threading.enumerate()
            if thread.name.startswith("tf_listener:")]


def robot_pose(node: Any, global_frame: str, base_frame: str) -> Any | None:
    """The robot's pose as a ``PoseStamped`` in ``global_frame``; None when TF has none."""
    from geometry_msgs.msg import PoseStamped
    from rclpy.time import Time

    try:
        transform = tf_buffer(node).lookup_transform(global_frame, base_frame, Time())
    except Exception as exc:  # tf2's LookupException, ExtrapolationException, ...
        node.get_logger().debug(f"no robot pose in {global_frame}: {exc}")
        return None
    pose = PoseStamped()
    pose.header = transform.header
    t = transform.transform
    pose.pose.position.x, pose.pose.position.y, pose.pose.position.z = (
        t.translation.x, t.translation.y, t.translation.z)
    pose.pose.orientation = t.rotation
    return pose
