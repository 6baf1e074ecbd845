"""Nav2's node palette (``nav2_behavior_tree``'s ``nav2_tree_nodes.xml``, Jazzy).

The action and condition nodes (leaves), controls and decorators Nav2's navigator trees
use, with Nav2's names, ports, port types and defaults (a test compares them with the
palette), the leaves talking to Nav2's servers by
Nav2's default names (``server_name`` / ``service_name`` change them). No leaf knows
whether the embedded simulator or a real Nav2 answers. Modules, by family:

- ``_bt_nodes``: Nav2's action and service bases on the leaf toolkit (goal or request
  sent once, polled, cancelled on a halt, verdict latched); ``_common``: the navigator's
  defaults, ports;
  ``_tf``: the robot's pose;
- ``planning``: ComputePathToPose, ComputePathThroughPoses, SmoothPath, FollowPath;
- ``behaviors``: Spin, BackUp, DriveOnHeading, Wait;
- ``navigators``: NavigateToPose, NavigateThroughPoses, CancelControl;
- ``costmaps``: ClearEntireCostmap, ClearCostmapAroundRobot, ClearCostmapExceptRegion;
- ``selectors``: ControllerSelector, PlannerSelector;
- ``path_tools``: RemovePassedGoals, TruncatePath;
- ``conditions``: GoalUpdated, GlobalUpdatedGoal, GoalReached, IsStuck, TimeExpired,
  PathExpiringTimer, WouldAControllerRecoveryHelp, WouldAPlannerRecoveryHelp;
  ``path_valid``: IsPathValid;
- ``controls``: RecoveryNode, PipelineSequence, RoundRobin;
- ``decorators``: RateController, SingleTrigger, GoalUpdatedController,
  PathLongerOnApproach; ``robot_decorators`` (the robot's state from the tree's context,
  :mod:`.robot_context`): DistanceController, SpeedController, GoalUpdater.

The registry finds the nodes through this package's names (it imports ``sar_plugins``'
modules one level deep).
"""

from .behaviors import BackUp, DriveOnHeading, Spin, Wait
from .conditions import (
    GlobalUpdatedGoal,
    GoalReached,
    GoalUpdated,
    IsStuck,
    PathExpiringTimer,
    TimeExpired,
    WouldAControllerRecoveryHelp,
    WouldAPlannerRecoveryHelp,
)
from .controls import PipelineSequence, RecoveryNode, RoundRobin
from .costmaps import ClearCostmapAroundRobot, ClearCostmapExceptRegion, ClearEntireCostmap
from .decorators import GoalUpdatedController, PathLongerOnApproach, RateController, SingleTrigger
from .navigators import CancelControl, NavigateThroughPoses, NavigateToPose
from .path_tools import RemovePassedGoals, TruncatePath
from .path_valid import IsPathValid
from .planning import ComputePathThroughPoses, ComputePathToPose, FollowPath, SmoothPath
from .robot_decorators import DistanceController, GoalUpdater, SpeedController
from .selectors import ControllerSelector, PlannerSelector

__all__ = [
    "BackUp", "CancelControl", "ClearCostmapAroundRobot", "ClearCostmapExceptRegion",
    "ClearEntireCostmap", "ComputePathThroughPoses", "ComputePathToPose", "ControllerSelector",
    "DistanceController", "DriveOnHeading", "FollowPath", "GlobalUpdatedGoal", "GoalReached",
    "GoalUpdated", "GoalUpdatedController", "GoalUpdater", "IsPathValid", "IsStuck",
    "NavigateThroughPoses", "NavigateToPose", "PathExpiringTimer", "PathLongerOnApproach",
    "PipelineSequence", "PlannerSelector", "RateController", "RecoveryNode",
    "RemovePassedGoals", "RoundRobin", "SingleTrigger", "SmoothPath", "SpeedController", "Spin",
    "TimeExpired", "TruncatePath", "Wait", "WouldAControllerRecoveryHelp",
    "WouldAPlannerRecoveryHelp",
]
