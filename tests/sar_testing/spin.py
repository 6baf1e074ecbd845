"""Kept for the tests that import it: the code lives in :mod:`sar_framework.testing.spin`."""

from sar_framework.testing.spin import call_service, ros_node, spin_until

__all__ = ["call_service", "ros_node", "spin_until"]
