"""NavigateToBase: drive back to the base station with Nav2."""

from __future__ import annotations

from sar_plugins.sar.events import SarKind

from sar_framework.engine.plugin import leaf

from ._pose_target import NAVIGATION_PARAMS, NavigateToTarget, NavigationTarget


@leaf(params=NAVIGATION_PARAMS, context=["zone_manager"])
class NavigateToBase(NavigateToTarget):
    """Send a Nav2 NavigateToPose goal to the base station and wait for the result.

    Same behaviour and bounds as NavigateToZone, with the ZoneManager's base pose as the
    goal. Logs ``All zones visited. Returning to base.`` when it sends the goal after every
    zone was reached (else the zones not reached, or how many are left, when used
    mid-mission) and ``Reached base station.`` on success. Wrap it in a OneShot
    (ON_COMPLETION) under a reactive Selector so the goal is sent only once.
    """

    def reached(self, target: NavigationTarget) -> None:
        """Tell that the target was reached."""
        self.events.emit(SarKind.BASE_REACHED, source=self, message=target.reached,
                         position=(target.x, target.y))

    def target(self) -> NavigationTarget:
        """Where to go now."""
        base = self.zone_manager.base_pose()
        remaining = self.zone_manager.total_zones() - self.zone_manager.current_index()
        skipped = self.zone_manager.skipped_zones()
        if remaining:
            announce = f"Returning to base with {remaining} zone(s) unvisited."
        elif skipped:
            announce = f"Zones done, not reached: {', '.join(skipped)}. Returning to base."
        else:
            announce = "All zones visited. Returning to base."
        return NavigationTarget(
            label="base station",
            x=base["x"],
            y=base["y"],
            yaw=base["yaw"],
            announce=announce,
            reached="Reached base station.",
        )
