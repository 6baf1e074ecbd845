"""The leaf toolkit: base classes for writing leaf plugins, with ROS or without.

Each is a py_trees behaviour whose declared params, context objects and ports arrive as
attributes of the same names, so a leaf usually needs no ``__init__``. The ROS ones get
their node the py_trees_ros way, ``setup(node=...)``, never block a tick, count every bound
on the node's clock and say why they ended in ``feedback_message``:

=======================  ==============================================================
:class:`ActionLeaf`      a ROS 2 action client (BehaviorTree.ROS2's ``RosActionNode``)
:class:`ServiceLeaf`     a ROS 2 service client (``RosServiceNode``)
:class:`PublisherLeaf`   publishes one message per tick (``RosTopicPubNode``)
:class:`TopicCondition`  a condition on a topic's newest message (``RosTopicSubNode``)
:class:`RosLeaf`         any other leaf with a ROS node and a latched verdict
:class:`StatefulLeaf`    long work without ROS (``on_start``/``on_running``/``on_halted``)
:class:`Leaf`            a plain leaf; :class:`Condition`: a plain condition
=======================  ==============================================================

The goal and request life cycles are usable alone: :class:`PolledGoal`, :class:`GoalBatch`
(many goals to one server), :class:`PolledServiceCall` and, for a condition that must answer
in its tick, :class:`TickServiceCall`. :func:`action_params`, :func:`service_params` and
:func:`topic_params` declare the params each ROS leaf reads (names, bounds, QoS), to put in
the leaf's ``@leaf(params=[...])``. Importing this package imports no ROS package.
"""

from sar_framework.leaves.action import ActionLeaf, action_params
from sar_framework.leaves.declared import interface_type
from sar_framework.leaves.goal_call import (
    STATUS_ABORTED,
    STATUS_CANCELED,
    STATUS_SUCCEEDED,
    GoalBatch,
    GoalEnd,
    GoalFailure,
    PolledGoal,
)
from sar_framework.leaves.plain import Condition, Leaf, StatefulLeaf
from sar_framework.leaves.ros_leaf import RosLeaf
from sar_framework.leaves.service import ServiceLeaf, service_params, service_timeout_params
from sar_framework.leaves.service_call import CallResult, PolledServiceCall
from sar_framework.leaves.tick_call import TickServiceCall
from sar_framework.leaves.topics import PublisherLeaf, TopicCondition, qos_of, topic_params

__all__ = [
    "STATUS_ABORTED", "STATUS_CANCELED", "STATUS_SUCCEEDED", "ActionLeaf", "CallResult",
    "Condition", "GoalBatch", "GoalEnd", "GoalFailure", "Leaf", "PolledGoal", "PolledServiceCall",
    "PublisherLeaf", "RosLeaf", "ServiceLeaf", "StatefulLeaf", "TickServiceCall",
    "TopicCondition",
    "action_params", "interface_type", "qos_of", "service_params", "service_timeout_params",
    "topic_params",
]
