"""CompleteZone: tell the fleet's zone coordinator the current zone was searched."""

from __future__ import annotations

from sar_framework.engine.plugin import leaf

from ._fleet import FINISH_PARAMS, FinishZoneLeaf


@leaf(params=FINISH_PARAMS, context=["zone_manager"])
class CompleteZone(FinishZoneLeaf):
    """Report the current (claimed) zone searched on ``/zone_coordinator/finish_zone``.

    SUCCESS once the coordinator accepts; FAILURE when it refuses (this robot no longer
    holds the zone: it was declared lost meanwhile), when there is no current zone, or on
    the service bounds.
    """

    OUTCOME = 0  # FinishZone.Request.SEARCHED
    VERB = "searched"
