"""The path from a tree file to a running tree: five hops, none back to a stage left.

``api.load_tree`` hands the file to ``checking.validate.validate_file``, which reads it
(``reading``) and then checks it (``checking``); ``load_tree`` then builds the TreeSpec
(``building``). The calls these two make are traced: each goes to the stage after the
one before, never back (docs/architecture.md draws the same path).
"""

from __future__ import annotations

import sys
from types import FrameType
from typing import Any

from sar_framework.engine import api
from sar_framework.engine.checking import validate
from sar_framework.engine.registry import Registry

from .conftest import FIXTURES

ENGINE = "sar_framework.engine."
STAGES = ("reading", "checking", "building")
#: The modules that hand the tree from one stage to the next, and their functions.
ORCHESTRATORS = {(api.__name__, "load_tree"), (api.__name__, "_validated"),
                 (validate.__name__, "validate_file")}


def stages_called(registry: Registry) -> list[str]:
    """The stage of every engine module the orchestrators call, in call order."""
    called: list[str] = []

    def note(frame: FrameType, event: str, _arg: Any) -> None:
        caller = frame.f_back
        if event != "call" or caller is None:
            return
        where = (caller.f_globals.get("__name__"), caller.f_code.co_name)
        module = frame.f_globals.get("__name__", "")
        if (module, frame.f_code.co_name) in ORCHESTRATORS:
            return  # the next hand-over, not a stage
        if where in ORCHESTRATORS and module != where[0] and module.startswith(ENGINE):
            stage = module[len(ENGINE):].partition(".")[0]
            called.append(stage if stage in STAGES else "shared")  # spec, registry...

    sys.setprofile(note)
    try:
        api.load_tree(FIXTURES / "search_and_rescue.yaml",
                      context={"zone_manager": object()}, registry=registry)
    finally:
        sys.setprofile(None)
    return called


def test_each_stage_follows_the_one_before_and_none_is_entered_twice(
        registry: Registry) -> None:
    called = [stage for stage in stages_called(registry) if stage != "shared"]
    in_turn = [stage for i, stage in enumerate(called) if i == 0 or called[i - 1] != stage]
    assert in_turn == list(STAGES), called
    hops = {module for module, _ in ORCHESTRATORS} | set(in_turn)  # api, validate, stages
    assert len(hops) <= 5, hops

