"""Built-in leaf plugins of sar_framework (import name ``sar_plugins``).

One module per leaf, and the package ``nav2`` (Nav2's palette as leaves, one module per
family; :mod:`sar_plugins.nav2`). Modules import ROS packages lazily, inside ``setup()``,
so validating or rendering a tree never needs ROS.

Every leaf is built on the public leaf toolkit, :mod:`sar_framework.leaves` (its service,
action and ROS bases); modules whose names start with ``_`` are shared helpers and hold no
plugin, e.g. ``_pose_target`` (the NavigateToPose leaf behind NavigateToZone and
NavigateToBase).
Leaves share state by reference, never through a blackboard: IsSurvivorDetected,
BroadcastSurvivorTF and NotifyBase name a DetectSurvivor leaf in ``detector``, and
NotifyBase names the BroadcastSurvivorTF leaf in ``broadcaster`` to report the
survivor id that leaf allocated for its TF frame (or took from the RegisterSurvivor leaf
named in its ``registrar``: a fleet's survivors counted once).
"""
