"""The search-and-rescue mission under ``ros2 launch``: ``tree.launch.py`` with the app's files.

    ros2 launch sar_framework search_and_rescue.launch.py [survivors_file:=...]
        [report_file:=FILE] [every argument of tree.launch.py: nav2:=, tree:=, speed:=...]

It includes ``tree.launch.py`` (any tree: Nav2, the apps' processes, the runner, the report)
and adds the search-and-rescue app's two files, as ``app_params``: the survivor table the
detect server answers from, and the report server's log of acknowledged survivors. By
default that log is ``reports.jsonl`` in the run's own folder, so a new mission never
inherits an earlier one's survivors; reusing a log across runs is explicit
(``report_file:=~/.ros/sar_reports.jsonl``).
"""

from __future__ import annotations

import shlex
from pathlib import Path

from launch.actions import DeclareLaunchArgument, IncludeLaunchDescription
from launch.launch_description_sources import PythonLaunchDescriptionSource
from launch.substitution import Substitution
from launch.substitutions import LaunchConfiguration
from sar_plugins.sar.servers.params import REPORT_PARAMETERS

from launch import LaunchContext, LaunchDescription
from sar_framework.ros.launch_nodes import package_file

REPORT_FILE = next(p for p in REPORT_PARAMETERS if p.name == "report_file")

ARGUMENTS = [
    DeclareLaunchArgument("survivors_file", default_value="config/survivors.yaml",
                          description="Survivor table the detect server answers from."),
    DeclareLaunchArgument("report_file", default_value=REPORT_FILE.default,
                          description="The report server's JSON Lines file of acknowledged "
                          "reports; empty: reports.jsonl in the run's folder. Name a file to "
                          "reuse its survivors across runs."),
]


def app_params(context: LaunchContext) -> str:
    """The app's files as ``tree.launch.py``'s ``app_params`` (file arguments resolved)."""
    def arg(name: str) -> str:
        return LaunchConfiguration(name).perform(context)

    entries = [f"detect.survivors_file:={package_file(arg('survivors_file'))}"]
    if arg("report_file"):
        entries.append("report.report_file:="
                       f"{Path(arg('report_file')).expanduser().absolute()}")
    return shlex.join(entries)


class AppParams(Substitution):
    """:func:`app_params`, performed once the arguments are known."""

    def perform(self, context: LaunchContext) -> str:
        """The ``app_params`` text."""
        return app_params(context)

    def describe(self) -> str:
        """How ``ros2 launch --print`` shows it."""
        return "AppParams(survivors_file, report_file)"


def generate_launch_description() -> LaunchDescription:
    """The app's arguments, then ``tree.launch.py`` (beside this file) with them."""
    source = PythonLaunchDescriptionSource(str(Path(__file__).with_name("tree.launch.py")))
    return LaunchDescription([*ARGUMENTS, IncludeLaunchDescription(
        source, launch_arguments=[("app_params", AppParams())])])
