"""The servers' parameters (``detect_survivor_server``, ``report_survivor_server``); no ROS.

Each server declares its table on its node (:mod:`sar_framework.ros.parameters`);
``sar-tree run`` checks ``--detect-param`` and ``--report-param`` against the same tables.
"""

from __future__ import annotations

from sar_framework.engine.param import Param
from sar_framework.mission.params_check import USE_SIM_TIME

SERVICE_NAME = "service_name"
ANSWER_DELAY = Param("answer_delay_wall_s", float, 0.0, "fault: the service answers this late "
                     "(wall clock)", minimum=0.0, unit="s")

DETECT_PARAMETERS: tuple[Param, ...] = (
    Param("survivors_file", str, "", "survivor table (YAML); '' = the repository's "
          "config/survivors.yaml"),
    Param(SERVICE_NAME, str, "detect_survivor", "the service's name (relative: a server "
          "started in /robot1 serves /robot1/detect_survivor)"),
    ANSWER_DELAY,
    USE_SIM_TIME,
)
"""Every parameter ``detect_survivor_server`` reads."""

REPORT_PARAMETERS: tuple[Param, ...] = (
    Param("report_file", str, "", "JSON Lines file of acknowledged reports; '' = "
          "$ROS_HOME/sar_reports.jsonl (~/.ros/sar_reports.jsonl)"),
    Param(SERVICE_NAME, str, "/report_survivor", "the service's name"),
    Param("global_frame", str, "map", "the frame reports must use"),
    Param("refuse_all", bool, False, "fault: the report service refuses every survivor"),
    ANSWER_DELAY,
    USE_SIM_TIME,
)
"""Every parameter ``report_survivor_server`` reads."""
