"""py_trees 2.2.3 .. 2.6.0: every version difference the engine cares about, in one place.

What differs between the two ends, as far as this engine goes:

* ``py_trees.decorators.ForEach`` exists only in 2.6 (blackboard based; not offered).
* ``Selector`` in 2.6 stops its children when one succeeds or all fail; 2.2.3 only
  sets its status. That is tick-time behaviour, not construction, so the engine
  builds the same objects on both.
* Composite constructors take ``list`` (2.2.3) or any ``Sequence`` (2.6) of
  children: the builder always passes a list.
* py_trees has no ``__version__``; the version comes from the distribution metadata.

Everything else the builder uses (composite, decorator and policy constructors,
``OneShotPolicy``, ``Status``) has the same signature in both.
"""

from __future__ import annotations

import importlib.metadata
from collections.abc import Sequence

import py_trees

#: Oldest and newest py_trees the engine is tested with.
SUPPORTED_RANGE = ("2.2.3", "2.6.0")


def _version() -> tuple[int, ...]:
    try:
        text = importlib.metadata.version("py_trees")
    except importlib.metadata.PackageNotFoundError:  # vendored or source checkout
        return (0,)
    parts = []
    for piece in text.split(".")[:3]:
        digits = "".join(c for c in piece if c.isdigit())
        parts.append(int(digits) if digits else 0)
    return tuple(parts)


#: The installed py_trees version, e.g. ``(2, 6, 0)``.
PY_TREES_VERSION: tuple[int, ...] = _version()


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


def composite_class(class_name: str) -> type[py_trees.composites.Composite]:
    """Return ``py_trees.composites.<class_name>`` (``Sequence``, ``Selector``, ``Parallel``)."""
    cls: type[py_trees.composites.Composite] = getattr(py_trees.composites, class_name)
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


def decorator_names() -> set[str]:
    """Return the names of the decorator classes this py_trees version offers."""
    base = py_trees.decorators.Decorator
    return {
        name
        for name, value in vars(py_trees.decorators).items()
        if isinstance(value, type) and issubclass(value, base) and value is not base
    }
