"""The search-and-rescue app's leaves: zones, survivors and the fleet's zone claims.

Registered under the entry-point group ``sar_framework.plugins`` (``pyproject.toml``), so
every installed registry has them; the core's built-in leaves (:mod:`sar_plugins`) do not
include them. One module per leaf; modules whose names start with ``_`` are shared helpers
and hold no plugin, e.g. ``_pose_target`` (the NavigateToPose leaf behind NavigateToZone and
NavigateToBase).

Leaves share state by reference, never through a blackboard: IsSurvivorDetected,
BroadcastSurvivorTF and NotifyBase name a DetectSurvivor leaf in ``detector``, and
NotifyBase names the BroadcastSurvivorTF leaf in ``broadcaster`` to report the
survivor id that leaf allocated for its TF frame (or took from the RegisterSurvivor leaf
named in its ``registrar``: a fleet's survivors counted once).
"""
