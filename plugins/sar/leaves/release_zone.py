"""ReleaseZone: give the current zone back to the fleet's zone coordinator."""

from __future__ import annotations

from sar_framework.engine.plugin import leaf

from ._fleet import FINISH_PARAMS, FinishZoneLeaf


@leaf(params=FINISH_PARAMS, context=["zone_manager"])
class ReleaseZone(FinishZoneLeaf):
    """Give the current (claimed) zone back on ``/zone_coordinator/finish_zone``.

    For a robot that could not reach the zone (after NavigateToZone failed): the zone goes
    back to auction and this robot never bids on it again. SUCCESS once the coordinator
    accepts; FAILURE when it refuses, when there is no current zone, or on the bounds.
    """

    OUTCOME = 1  # FinishZone.Request.GIVEN_BACK
    VERB = "given back"
