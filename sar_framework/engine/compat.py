"""py_trees 2.2.3 .. 2.6.0: every version difference the engine cares about, in one place.

What differs between the two ends, as far as this engine goes:

* ``py_trees.decorators.ForEach`` exists only in 2.6 (blackboard based; not offered).
* ``Selector`` in 2.6 stops its children when one succeeds or all fail; 2.2.3 only
  sets its status. That is tick-time behaviour, not construction, so the engine
  builds the same objects on both.
* Composite constructors take ``list`` (2.2.3) or any ``Sequence`` (2.6) of
  children: the builder always passes a list.

Everything else the builder uses (composite, decorator and policy constructors,
``OneShotPolicy``, ``Status``) has the same signature in both.
"""

from __future__ import annotations

from collections.abc import Sequence

import py_trees


def decorator_class(class_name: str) -> type[py_trees.decorators.Decorator]:
    """Return ``py_trees.decorators.<class_name>``.

    Args:
        class_name: A decorator class name from :mod:`.node_kinds` (``OneShot``).

    Returns:
        The class.

    Raises:
        AttributeError: When this py_trees version lacks it.
    """
    cls: type[py_trees.decorators.Decorator] = getattr(py_trees.decorators, class_name)
    return cls


def parallel_policy(
    policy: str, *, synchronise: bool, selected: Sequence[py_trees.behaviour.Behaviour] = ()
) -> py_trees.common.ParallelPolicy.Base:
    """Build a parallel policy from its tree-file spelling.

    Args:
        policy: ``success_on_all``, ``success_on_one`` or ``success_on_selected``.
        synchronise: The policy's synchronise flag (ignored by ``success_on_one``).
        selected: The children that must succeed, for ``success_on_selected``.

    Returns:
        The policy object.
    """
    policies = py_trees.common.ParallelPolicy
    if policy == "success_on_all":
        return policies.SuccessOnAll(synchronise=synchronise)
    if policy == "success_on_one":
        return policies.SuccessOnOne()
    return policies.SuccessOnSelected(children=list(selected), synchronise=synchronise)


def one_shot_policy(policy: str) -> py_trees.common.OneShotPolicy:
    """Return the ``OneShotPolicy`` member for ``on_completion`` / ``on_successful_completion``."""
    return py_trees.common.OneShotPolicy[policy.upper()]


def status(name: str) -> py_trees.common.Status:
    """Return the ``Status`` member for ``success`` / ``failure`` / ``running``."""
    return py_trees.common.Status[name.upper()]

