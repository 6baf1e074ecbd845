"""Embedded Nav2 stand-in: world geometry, occupancy map, planner and diff-drive model.

The modules ``world``, ``occupancy``, ``planner`` and ``drive`` are plain Python + numpy
(no ROS); the ROS nodes that serve ``navigate_to_pose`` and the simulated robot build on them.
"""
