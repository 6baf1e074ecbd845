"""BehaviorTree.CPP 4.7.3's controls and built-in leaves in py_trees.

Each class ticks its children exactly as its BT.CPP counterpart does (tick order,
halting and resetting of children, SKIPPED handling: see :mod:`.base`), so a tree
exported to BT.CPP behaves the same tick by tick (``tests/interop`` checks it against
the real library). The decorators are in :mod:`..decorators`. One concept per module:

- :mod:`.sequences`: (Reactive)Sequence, SequenceWithMemory, (Reactive)Fallback.
- :mod:`.parallels`: Parallel, ParallelAll.
- :mod:`.conditionals`: IfThenElse, WhileDoElse, Switch2..Switch6.
- :mod:`.leaves`: AlwaysSuccess, AlwaysFailure, Sleep, SetBlackboard, UnsetBlackboard.
- :mod:`.read_ports`: the ports bound to entries (Timeout's ``msec: "{t}"``...), read by
  the node when BT.CPP reads them.
"""
