"""BehaviorTree.CPP 4.7.3's controls and decorators (and Nav2's ROS-free ones) in py_trees.

Each class ticks its children exactly as its BT.CPP counterpart does (tick order,
halting and resetting of children, SKIPPED handling: see :mod:`.base`), so a tree
exported to BT.CPP behaves the same tick by tick (``tests/interop`` checks it against
the real library). The modules, one concept each:

- :mod:`.sequences`: Sequence, SequenceWithMemory, ReactiveSequence, Fallback,
  ReactiveFallback.
- :mod:`.parallels`: Parallel, ParallelAll.
- :mod:`.conditionals`: IfThenElse, WhileDoElse, Switch2..Switch6.
- :mod:`.converters`: Inverter, ForceSuccess, ForceFailure, KeepRunningUntilFailure.
- :mod:`.loops`: Repeat, RetryUntilSuccessful, RunOnce.
- :mod:`.timing`: Delay, Timeout (on a given clock).
- :mod:`.updated`: SkipUnlessUpdated, WaitValueUpdate, WasEntryUpdated.
- :mod:`.queues`: LoopInt, LoopBool, LoopDouble, LoopString.
- :mod:`.leaves`: AlwaysSuccess, AlwaysFailure, Sleep, SetBlackboard, UnsetBlackboard.
- :mod:`.nav2_controls`, :mod:`.nav2_decorators`: RecoveryNode, PipelineSequence,
  RoundRobin; RateController, SingleTrigger.
- :mod:`.read_ports`: the ports bound to entries (Timeout's ``msec: "{t}"``...), read by
  the node when BT.CPP reads them.

No ROS is imported here.
"""
