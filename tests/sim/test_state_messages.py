"""The physics loop's refilled ``/tf`` and odometry messages equal freshly built ones."""

import pytest
from tf2_msgs.msg import TFMessage

from sar_framework.sim import messages
from sar_framework.sim.world import Pose2D

SPAWN = Pose2D(1.0, 2.0, 0.3)
FRAMES = ("map", "odom", "base_link")


@pytest.mark.parametrize("localized_first", [True, False])
def test_refilled_messages_equal_fresh_ones_state_after_state(localized_first: bool) -> None:
    state = messages.StateMessages(SPAWN, FRAMES)
    states = [  # (pose in odom, twist, stamp ns, localised), each refilling the last
        (Pose2D(0.5, -0.2, 1.1), (0.2, -0.3), 1_234_567_890_123, localized_first),
        (Pose2D(3.0, 4.0, -2.0), (0.0, 0.1), 5, not localized_first),
        (Pose2D(-0.1, 0.2, 3.0), (0.3, 0.0), 2_000_000_001, True),
    ]
    for pose, twist, stamp_ns, localized in states:
        tf = state.fill(pose, twist, stamp_ns, localized=localized)
        fresh = [messages.transform("odom", "base_link", pose, stamp_ns)]
        if localized:
            fresh.insert(0, messages.transform("map", "odom", SPAWN, stamp_ns))
        assert tf == TFMessage(transforms=fresh)
        assert state.odometry == messages.odometry(pose, twist, ("odom", "base_link"), stamp_ns)
