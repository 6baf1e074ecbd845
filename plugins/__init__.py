"""Built-in leaf plugins of sar_framework (import name ``sar_plugins``).

One module per neutral leaf (``Log``, ``Dwell``), and the package ``nav2`` (Nav2's palette
as leaves, one module per family; :mod:`sar_plugins.nav2`). Modules import ROS packages
lazily, inside ``setup()``, so validating or rendering a tree never needs ROS.

Every leaf is built on the public leaf toolkit, :mod:`sar_framework.leaves` (its service,
action and ROS bases). The apps' own leaves live in their apps (the search-and-rescue
app's in :mod:`sar_plugins.sar.leaves`) and are registered like any installed plugin.
"""
