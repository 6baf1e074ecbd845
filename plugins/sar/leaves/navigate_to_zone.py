"""NavigateToZone: drive to the ZoneManager's current zone with Nav2."""

from __future__ import annotations

from sar_framework.engine.plugin import leaf

from ._pose_target import NAVIGATION_PARAMS, NavigateToTarget, NavigationTarget


@leaf(params=NAVIGATION_PARAMS, context=["zone_manager"])
class NavigateToZone(NavigateToTarget):
    """Send a Nav2 NavigateToPose goal to the current zone and wait for the result.

    RUNNING while Nav2 drives, SUCCESS when the goal succeeds, FAILURE when it is rejected,
    aborted or cancelled, when the action server is not ready within ``server_timeout_s`` or
    the goal does not finish within ``navigation_timeout_s``. The goal is sent when the leaf
    starts (logging ``--- Zone 1/4: zone_a (-3.00, 3.00) ---``) and cancelled if the leaf is
    halted first. Logs ``Reached zone_a.`` on success. Fails when no zone is left.
    """

    def reached(self, target: NavigationTarget) -> None:
        """Tell that the target was reached."""
        self.zone_manager.mark_reached(target.zone_id)  # the zone manager tells the events

    def target(self) -> NavigationTarget:
        """Where to go now."""
        zone = self.zone_manager.current_zone()  # IndexError (a LookupError) when exhausted
        index, total = self.zone_manager.current_index() + 1, self.zone_manager.total_zones()
        where = f"({zone['x']:.2f}, {zone['y']:.2f})"
        return NavigationTarget(
            label=zone["id"],
            x=zone["x"],
            y=zone["y"],
            yaw=zone["yaw"],
            announce=f"--- Zone {index}/{total}: {zone['id']} {where} ---",
            reached=f"Reached {zone['id']}.",
            zone_id=zone["id"],
        )
