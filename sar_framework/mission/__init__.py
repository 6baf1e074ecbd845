"""A mission's parts above the engine in plain Python (no ROS): its parameters, processes, end."""
