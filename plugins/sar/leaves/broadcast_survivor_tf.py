"""BroadcastSurvivorTF: publish a static TF frame for a detected survivor."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from py_trees.common import Status
from sar_plugins.sar.events import SarKind

from sar_framework.engine.plugin import Param, leaf
from sar_framework.leaves import RosLeaf

if TYPE_CHECKING:
    from sar_plugins.sar.zone_manager import ZoneManager

    from sar_framework.ros.static_tf import StaticBroadcaster

    from .detect_survivor import DetectSurvivor
    from .register_survivor import RegisterSurvivor


@leaf(
    params=[
        Param("detector", ref="DetectSurvivor",
              description="id of the DetectSurvivor leaf whose survivor to broadcast."),
        Param("parent_frame", str, default="map",
              description="Parent frame of the survivor frame (the detection's frame)."),
        Param("registrar", ref="RegisterSurvivor", default=None,
              description="id of a RegisterSurvivor leaf: broadcast the fleet id it was "
                          "given instead of allocating one (fleets: survivors counted once)."),
    ],
    context=["zone_manager"],
)
class BroadcastSurvivorTF(RosLeaf):
    """Broadcast a static transform parent_frame -> survivor_N at the detected survivor.

    Each activation allocates one new id with ``zone_manager.next_survivor_id()`` (or, with
    ``registrar`` set, takes the fleet-wide id that RegisterSurvivor leaf was given) and sends
    it on ``/tf_static`` (translation from the detection, identity rotation), then succeeds
    in the same tick. The allocated id is readable through :meth:`survivor_id`, which is how
    NotifyBase reports the same id. FAILURE when the detector holds no survivor, or the
    registrar holds no id for this robot to broadcast. Put it in a
    Sequence with ``memory=True`` so a RUNNING sibling after it does not re-tick it (each
    re-tick allocates another id).

    Args:
        name: The behaviour's name.
        zone_manager: The mission's shared zone state (allocates survivor ids).
        detector: The DetectSurvivor leaf.
        parent_frame: Parent frame of the survivor frames.
        registrar: The RegisterSurvivor leaf whose fleet id to use, or None.
    """

    def __init__(self, name: str, *, zone_manager: ZoneManager, detector: DetectSurvivor,
                 parent_frame: str, registrar: RegisterSurvivor | None) -> None:
        super().__init__(name)
        self.zone_manager = zone_manager
        self.detector = detector
        self.parent_frame = parent_frame
        self.registrar = registrar
        self._broadcaster: StaticBroadcaster | None = None
        self._survivor_id: str | None = None

    def survivor_id(self) -> str | None:
        """The child frame id of the last survivor broadcast, or None before the first."""
        return self._survivor_id

    def setup(self, **kwargs: Any) -> None:
        """Take the ROS node and create the static broadcaster (tf2_ros or its stand-in).

        Args:
            **kwargs: Must hold ``node``.
        """
        super().setup(**kwargs)
        from sar_framework.ros.static_tf import make_static_broadcaster

        self._broadcaster = make_static_broadcaster(self.node)

    def initialise(self) -> None:
        """Reset the latch for a new broadcast."""
        self.reset_latch()

    def update(self) -> Status:
        """Allocate an id, send the frame and return SUCCESS (FAILURE without a survivor)."""
        if self._done:
            return self.verdict()
        pose = self.detector.survivor_pose()
        if not self.detector.was_found() or pose is None:
            return self.latch(False, "no survivor detected to broadcast")
        if self._broadcaster is None:
            raise RuntimeError(f"BroadcastSurvivorTF '{self.name}' used before setup(node=...)")
        from geometry_msgs.msg import TransformStamped

        if self.registrar is None:
            child = self.zone_manager.next_survivor_id()
        else:
            fleet_id = self.registrar.survivor_id()
            if fleet_id is None:
                return self.latch(False, f"no fleet survivor id from {self.registrar.name} "
                                          "to broadcast")
            child = fleet_id
        transform = TransformStamped()
        transform.header.stamp = self.node.get_clock().now().to_msg()
        transform.header.frame_id = self.parent_frame
        transform.child_frame_id = child
        transform.transform.translation.x, transform.transform.translation.y = pose
        transform.transform.rotation.w = 1.0
        self._broadcaster.sendTransform(transform)
        self._survivor_id = child
        message = (f"Broadcast static TF {self.parent_frame} -> {child} at "
                   f"({pose[0]:.2f}, {pose[1]:.2f}).")
        self.events.emit(SarKind.SURVIVOR_BROADCAST, source=self, survivor_id=child,
                         message=message, position=pose)
        return self.latch(True, message)
