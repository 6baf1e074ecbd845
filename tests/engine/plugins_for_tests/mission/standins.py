"""Stand-ins for the nine mission leaves: same names, params and references, no ROS."""

from __future__ import annotations

import py_trees

from sar_framework.engine.plugin import Param, leaf

Status = py_trees.common.Status


class _Leaf(py_trees.behaviour.Behaviour):
    """Returns SUCCESS; remembers its constructor kwargs."""

    def __init__(self, name: str, **kwargs: object) -> None:
        super().__init__(name)
        self.kwargs = kwargs

    def update(self) -> Status:
        return Status.SUCCESS


@leaf(context=["zone_manager"])
class ZonesRemaining(_Leaf):
    """Condition: zones are left to visit."""


@leaf(
    params=[Param("timeout_s", float, default=120.0, exclusive_minimum=0.0,
                  description="Give up after this many seconds.")],
    context=["zone_manager"],
)
class NavigateToZone(_Leaf):
    """Drive to the current zone."""


@leaf(params=[Param("service", str, default="/detect_survivor", description="Service name.")],
      context=["zone_manager"])
class DetectSurvivor(_Leaf):
    """Ask the detector about the current zone."""

    def was_found(self) -> bool:
        return True


@leaf(params=[Param("detector", ref="DetectSurvivor", description="The detection to read.")])
class IsSurvivorDetected(_Leaf):
    """Condition: the detector found someone."""


@leaf(params=[Param("detector", ref="DetectSurvivor")], context=["zone_manager"])
class BroadcastSurvivorTF(_Leaf):
    """Broadcast the survivor's static transform."""


@leaf(params=[Param("detector", ref="DetectSurvivor"),
              Param("broadcaster", ref="BroadcastSurvivorTF")])
class NotifyBase(_Leaf):
    """Report the survivor to the base."""


@leaf(context=["zone_manager"])
class LogNoDetection(_Leaf):
    """Log that the zone was empty."""


@leaf(context=["zone_manager"])
class AdvanceZone(_Leaf):
    """Move on to the next zone."""


@leaf(params=[Param("timeout_s", float, default=120.0, exclusive_minimum=0.0)],
      context=["zone_manager"])
class NavigateToBase(_Leaf):
    """Drive back to the base station."""
