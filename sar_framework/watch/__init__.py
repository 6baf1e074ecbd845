"""``sar-tree watch``: the running tree in the terminal, refreshed as it ticks.

- :mod:`.view`: one frame drawn with rich from a tree status document (no ROS);
- :mod:`.command`: the command, following ``/sar_tree/status`` with a rich ``Live``
  display (:mod:`sar_framework.runner.tree_status` publishes it);
- :mod:`.child`: ``sar-tree run --watch``, the watcher as a child in the run's terminal.
"""
