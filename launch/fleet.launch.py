"""Several robots' mission under ``ros2 launch``: N robots in one embedded simulator.

    ros2 launch sar_framework fleet.launch.py [robots:=3 | fleet_file:=FILE]
        [tree:=fleet_search] [any argument of search_and_rescue.launch.py]

``search_and_rescue.launch.py`` with ``nav2:=embedded``, three robots and the fleet's tree
by default: it starts what ``sar-tree run TREE --robots N``/``--fleet FILE`` starts (one
description, :mod:`sar_framework.mission.processes`) and ends once every runner has ended,
exit 0 when every mission succeeded. Every other argument is the included launch's.
"""

from __future__ import annotations

from pathlib import Path

from launch.actions import DeclareLaunchArgument, IncludeLaunchDescription
from launch.launch_description_sources import PythonLaunchDescriptionSource
from launch.substitutions import LaunchConfiguration

from launch import LaunchDescription

DEFAULTS = {"robots": "3", "tree": "fleet_search.yaml"}
"""The arguments whose defaults differ from the included launch's."""


def generate_launch_description() -> LaunchDescription:
    """The included launch, embedded, with this launch's defaults."""
    arguments = [DeclareLaunchArgument(name, default_value=value,
                                       description="As search_and_rescue.launch.py's.")
                 for name, value in DEFAULTS.items()]
    passed = [("nav2", "embedded"), *((name, LaunchConfiguration(name)) for name in DEFAULTS)]
    source = PythonLaunchDescriptionSource(
        str(Path(__file__).with_name("search_and_rescue.launch.py")))
    return LaunchDescription([*arguments, IncludeLaunchDescription(
        source, launch_arguments=passed)])
