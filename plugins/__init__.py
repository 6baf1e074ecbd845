"""Built-in leaf plugins of sar_framework (import name ``sar_plugins``).

One module per leaf, and the package ``nav2`` (Nav2's palette as leaves, one module per
family; :mod:`sar_plugins.nav2`). Modules import ROS packages lazily, inside ``setup()``,
so validating or rendering a tree never needs ROS.

Modules whose names start with ``_`` are shared helpers and hold no plugin:
``_ros_leaf`` (the ROS node and the ``_done``/``_success`` verdict latch),
``_service_call`` (one bounded, polled service request), ``_service_leaf`` (the service
leaf behind DetectSurvivor and NotifyBase) and ``_navigation`` (the NavigateToPose client
behind NavigateToZone and NavigateToBase).
Leaves share state by reference, never through a blackboard: IsSurvivorDetected,
BroadcastSurvivorTF and NotifyBase name a DetectSurvivor leaf in ``detector``, and
NotifyBase names the BroadcastSurvivorTF leaf in ``broadcaster`` to report the
survivor id that leaf allocated for its TF frame (or took from the RegisterSurvivor leaf
named in its ``registrar``: a fleet's survivors counted once).
"""
