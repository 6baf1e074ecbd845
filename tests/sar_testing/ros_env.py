"""Kept for the tests that import it: the code lives in :mod:`sar_framework.testing.ros_env`."""

from sar_framework.testing.ros_env import DomainLease, apply_local_ros_env, lease_domain_id

__all__ = ["DomainLease", "apply_local_ros_env", "lease_domain_id"]
