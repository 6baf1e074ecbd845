"""The tree runner, ``sar-mission-runner``: one ROS node that loads a tree file and ticks it.

- :mod:`.node`: the node, its start-up order, its stop and exit codes (``main``);
- :mod:`.settings`: its parameters read from its table (:mod:`sar_framework.mission.runner_params`);
- :mod:`.nav2_startup`, :mod:`.lifecycle_probe`, :mod:`.basic_navigator`: AMCL seeded, Nav2
  awaited;
- :mod:`.tree_ticker`: py_trees_ros' ``BehaviourTree`` when importable, else the fallback;
- :mod:`.status_file`, :mod:`.reasons`: the JSON status file and its failure reasons;
- what it publishes, read by ``sar-tree run``, ``watch`` and the recorder:
  :mod:`.mission_events` and :mod:`.event_topic` (``/sar_mission/events``, ``events.jsonl``),
  :mod:`.tree_status` (``/sar_tree/status``, one document per tick).

Helpers the leaves and servers share with the runner (QoS, static TF, parameter
declarations, stop signals) are in :mod:`sar_framework.ros`. Importing this package
imports nothing from ROS.
"""
