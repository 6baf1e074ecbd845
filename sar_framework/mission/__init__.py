"""Mission state for the search-and-rescue tree (plain Python, no ROS)."""

from sar_framework.mission.zone_manager import ZoneManager

__all__ = ["ZoneManager"]
