"""TF topics per robot: the remapping nav2_bringup's launch gives every Nav2 node.

``bringup_launch.py`` remaps ``/tf`` to ``tf`` and ``/tf_static`` to ``tf_static`` for
every node, unconditionally: in the root namespace nothing changes, and a robot started
with ``-r __ns:=/robot1`` reads and writes ``/robot1/tf`` and ``/robot1/tf_static`` (the
frames keep their names: ``map``, ``odom``, ``base_link``). tf2_ros's listener and
broadcasters use the absolute names, so a node that hosts them takes these arguments.
"""

from __future__ import annotations

__all__ = ["TF_REMAP_ARGS"]

TF_REMAP_ARGS = ["--ros-args", "-r", "/tf:=tf", "-r", "/tf_static:=tf_static"]
"""Node-local ``cli_args`` (``rclpy.node.Node(cli_args=...)``) for the namespace's TF."""
