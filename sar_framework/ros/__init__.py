"""ROS 2 helpers shared by the mission leaves, the servers and the runner.

Unlike :mod:`sar_framework.engine`, modules here import ``rclpy`` and message
packages, so import them only where ROS is actually used (e.g. inside a leaf's
``setup()``). Importing this package itself imports nothing from ROS.
"""
