"""The recorder's parameters (``sar_recorder``); no ROS here."""

from __future__ import annotations

from sar_framework.engine.param import Param
from sar_framework.mission.params_check import USE_SIM_TIME

RECORDER_PARAMETERS: tuple[Param, ...] = (
    Param("output", str, "", "the .mcap file to write (must be set)"),
    Param("tree", str, "", "the tree file, attached to the recording"),
    Param("params_file", str, "", "the mission parameter file, attached to the recording"),
    Param("plugin_path", str | list[str], "",
          "local plugin modules or folders the run used (os.pathsep-separated), attached"),
    Param("app_topics", list[str], None,
          "the apps' topics to record too, each 'NAME TYPE' (their services' events)"),
    USE_SIM_TIME,
)
"""Every parameter ``sar_recorder`` reads."""
