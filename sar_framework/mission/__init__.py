"""The search-and-rescue mission in plain Python (no ROS): its state, parameters, processes."""

from sar_framework.mission.zone_manager import ZoneManager

__all__ = ["ZoneManager"]
