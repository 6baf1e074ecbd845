"""Scripts and script nodes on py_trees' real blackboard, through BlackboardVariables."""

from __future__ import annotations

import py_trees
import pytest
from py_trees.blackboard import Blackboard
from py_trees.common import Status

from sar_framework.engine.nodes.script_nodes import (
    ElseStatus,
    Precondition,
    PrePostConditions,
    Script,
)
from sar_framework.engine.nodes.skipping import was_skipped
from sar_framework.engine.scripting import ScriptError, compile_script
from sar_framework.engine.variables import BlackboardVariables

from .port_setup import clean_blackboard  # noqa: F401 (pytest fixture)


def variables_for(owner: str, script_texts: list[str], keys: dict[str, str]) -> BlackboardVariables:
    """The view a builder would give: every name the scripts use, writable where written."""
    scripts = [compile_script(text) for text in script_texts]
    names = {name for s in scripts for name in (*s.reads, *s.writes)}
    writes = {name for s in scripts for name in s.writes}
    return BlackboardVariables(owner, {name: keys[name] for name in names}, writable=writes)


def test_a_script_reads_and_writes_absolute_keys() -> None:
    Blackboard.set("/zones/count", 2)
    Blackboard.set("/goal", "zone_b")
    keys = {"count": "/zones/count", "@goal": "/goal", "label": "/Sub_0/label"}
    text = "count += 1; label := @goal .. '#' .. count"
    node = Script("label", compile_script(text), variables_for("label", [text], keys))
    node.tick_once()
    assert node.status == Status.SUCCESS
    assert Blackboard.get("/zones/count") == 3
    assert Blackboard.get("/Sub_0/label") == "zone_b#3"


def test_an_unset_entry_is_a_script_error() -> None:
    text = "missing + 1"
    variables = variables_for("n", [text], {"missing": "/missing"})
    with pytest.raises(ScriptError, match="'missing' has no value"):
        compile_script(text).run(variables)


def test_writing_a_read_only_name_is_a_script_error() -> None:
    Blackboard.set("/x", 1)
    variables = BlackboardVariables("n", {"x": "/x"})  # read-only
    with pytest.raises(ScriptError, match="cannot write 'x'") as caught:
        compile_script("y := 0; x = 2").run(BlackboardVariables("m", {"x": "/x", "y": "/y"},
                                                                writable=["y"]))
    assert caught.value.column == 9
    assert compile_script("x + 1").run(variables) == 2
    assert Blackboard.get("/x") == 1


def test_entry_types_are_kept_on_the_blackboard() -> None:
    Blackboard.set("/n", 5)
    variables = BlackboardVariables("n", {"n": "/n"}, writable=["n"])
    with pytest.raises(ScriptError, match=r"cannot store float 2\.5 in 'n'"):
        compile_script("n /= 2").run(variables)
    assert compile_script("n = 4.0").run(variables) == 4
    assert type(Blackboard.get("/n")) is int


def test_pre_and_post_conditions_on_the_blackboard() -> None:
    Blackboard.set("/battery", 80.0)
    Blackboard.set("/aborts", 0)
    keys = {"battery": "/battery", "aborts": "/aborts"}
    texts = ["battery > 20", "aborts += 1"]
    variables = variables_for("drive", texts, keys)
    drive = py_trees.behaviours.Running(name="Drive")
    node = PrePostConditions("drive", drive, variables, while_=compile_script(texts[0]),
                             on_halted=compile_script(texts[1]))
    node.tick_once()
    assert node.status == Status.RUNNING
    Blackboard.set("/battery", 15.0)
    node.tick_once()
    assert node.status == Status.SUCCESS and was_skipped(node)
    assert Blackboard.get("/aborts") == 1
    assert drive.status == Status.INVALID


def test_a_precondition_on_a_root_entry() -> None:
    Blackboard.set("/mode", 2)
    variables = BlackboardVariables("p", {"@mode": "/mode"})
    child = py_trees.behaviours.Success(name="act")
    node = Precondition("p", child, compile_script("@mode == AUTO", enums={"AUTO": 2}),
                        variables, ElseStatus.SKIPPED)
    node.tick_once()
    assert (node.status, was_skipped(node), child.status) == (
        Status.SUCCESS, False, Status.SUCCESS)
    Blackboard.set("/mode", 1)
    node.tick_once()
    assert (node.status, was_skipped(node)) == (Status.SUCCESS, True)
