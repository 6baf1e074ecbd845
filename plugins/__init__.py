"""Built-in leaf plugins of sar_framework (import name ``sar_plugins``).

One module per leaf. Modules import ROS packages lazily, inside ``setup()``,
so validating or rendering a tree never needs ROS.
"""
