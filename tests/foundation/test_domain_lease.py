"""The domain lease skips domains that processes without a lease already use.

A developer's ``sar-tree run`` or ``ros2 launch`` on a fixed ``ROS_DOMAIN_ID`` takes no
lease; a test run that leased the same id saw that mission's ``/clock``, ``/tf`` and
status topics beside its own (a robot that turned by exactly 0.0, a runner on two clocks).
"""

from __future__ import annotations

import pytest
from sar_testing.ros_env import lease_domain_id

pytestmark = pytest.mark.ros


def test_a_domain_a_participant_already_uses_is_not_leased() -> None:
    import rclpy
    from rclpy.context import Context
    from rclpy.node import Node

    probe = lease_domain_id()  # the id this process would be given next
    taken = probe.domain_id
    probe.release()
    context = Context()
    rclpy.init(context=context, domain_id=taken)  # a process on `taken` without a lease
    node = Node("unleased_mission", context=context)
    try:
        lease = lease_domain_id()
        try:
            assert lease.domain_id != taken
        finally:
            lease.release()
    finally:
        node.destroy_node()
        rclpy.shutdown(context=context)
    again = lease_domain_id()  # free once that participant is gone
    try:
        assert again.domain_id == taken
    finally:
        again.release()
