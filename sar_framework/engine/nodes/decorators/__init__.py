"""BehaviorTree.CPP 4.7.3's decorators in py_trees.

Each ticks its child as its BT.CPP counterpart does (:mod:`..controls.base`):

- :mod:`.converters`: Inverter, ForceSuccess, ForceFailure, KeepRunningUntilFailure.
- :mod:`.loops`: Repeat, RetryUntilSuccessful, RunOnce.
- :mod:`.timing`: Delay, Timeout (on a given clock).
- :mod:`.updated`: SkipUnlessUpdated, WaitValueUpdate, WasEntryUpdated.
- :mod:`.queues`: LoopInt, LoopBool, LoopDouble, LoopString.
"""
