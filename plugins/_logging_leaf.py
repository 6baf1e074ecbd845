"""LoggingLeaf: the base of leaves whose work is saying one line.

Not a plugin itself (it carries no ``@leaf`` mark), and it imports no ROS package.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import py_trees

if TYPE_CHECKING:
    from rclpy.node import Node


class LoggingLeaf(py_trees.behaviour.Behaviour):
    """A leaf that logs to the ROS node's logger when ``setup(node=...)`` gave one.

    Without a node (a tree ticked outside ROS) the line goes to the py_trees logger.

    Args:
        name: The behaviour's name.
    """

    def __init__(self, name: str) -> None:
        super().__init__(name=name)
        self._node: Node | None = None

    def setup(self, **kwargs: Any) -> None:
        """Keep the ROS node, if any, for logging.

        Args:
            **kwargs: May hold ``node``.
        """
        self._node = kwargs.get("node")

    def say(self, line: str, *, warning: bool = False) -> None:
        """Make ``line`` the feedback message and log it (info, or warning).

        Args:
            line: What to say.
            warning: Log as a warning instead of info.
        """
        self.feedback_message = line
        logger = self._node.get_logger() if self._node is not None else self.logger
        if warning:
            logger.warning(line)
        else:
            logger.info(line)
