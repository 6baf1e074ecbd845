"""The zone coordinator's parameters (``zone_coordinator``): one table, no ROS.

It reads the mission parameter file the runners read (``zone_order``, ``zones.*``: the same
entries as the app's table, :data:`~sar_framework.mission.runner_params.MISSION_PARAMETERS`)
and its own settings below.
"""

from __future__ import annotations

from sar_plugins.sar.params import MISSION_PARAMETERS

from sar_framework.engine.param import Param
from sar_framework.mission.params_check import USE_SIM_TIME

_MISSION = tuple(p for p in MISSION_PARAMETERS
                 if p.name == "zone_order" or p.name.startswith("zones."))

ROBOT_TIMEOUT = Param("robot_timeout_wall_s", float, 3.0, "a robot silent on "
                      "/zone_coordinator/heartbeat this long is lost (wall clock)",
                      exclusive_minimum=0.0, unit="s")
BID_WINDOW = Param("bid_window_wall_s", float, 2.0, "an auction round closes when every bidder "
                   "bid or after this long (wall clock)", exclusive_minimum=0.0, unit="s")
EVENTS_FILE = Param("events_file", str, "", "JSON Lines file of the coordinator's events "
                    "('' = none)")
SURVIVOR_RADIUS = Param("survivor_radius_m", float, 1.0, "survivors found within this "
                        "distance of a known one are the same survivor (the survivor "
                        "registry)", exclusive_minimum=0.0, unit="m")
ABANDON_AFTER = Param("abandon_after_rounds", int, 2, "a zone no live robot can reach "
                      "(every one bid inf) in this many rounds in a row is abandoned",
                      minimum=1)
ROBOTS = Param("robots", list[str], None, "the fleet's robot names: the first auction "
               "round waits for each to ask for work (unset: every robot heard so far)")
START_WAIT = Param("start_wait_wall_s", float, 10.0, "the first auction round waits this "
                   "long at most for the fleet to ask for work, from the first robot asking; "
                   "then it opens with the robots waiting (wall clock)", minimum=0.0, unit="s")

COORDINATOR_PARAMETERS: tuple[Param, ...] = (
    *_MISSION, ROBOT_TIMEOUT, BID_WINDOW, EVENTS_FILE, SURVIVOR_RADIUS, ABANDON_AFTER,
    ROBOTS, START_WAIT, USE_SIM_TIME,
)
"""Every parameter ``zone_coordinator`` reads."""
