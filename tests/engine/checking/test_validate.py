"""Every error class: the exact FILE:LINE:COL and message, all collected in one pass."""

from __future__ import annotations

import pytest

from ..conftest import Checker

HEAD = "format: 1\nroot:\n"


def tree(body: str) -> str:
    """A tree file whose root is ``body`` (indented by two spaces)."""
    return HEAD + "".join(f"  {line}\n" for line in body.strip("\n").split("\n"))


CASES = {
    "yaml_syntax": (
        "format: 1\nroot:\n  sequence: {memory: true, children: [Tick: {}\n",
        ["tree.yaml:4:1: error: YAML: while parsing a flow sequence, expected ',' or ']', "
         "but got '<stream end>'"],
    ),
    "yaml_tab": (
        "format: 1\nroot:\n\tTick: {}\n",
        ["tree.yaml:3:1: error: YAML: while scanning for the next token, found character "
         "'\\t' that cannot start any token"],
    ),
    "unknown_top_level_key": (
        "format: 1\nnmae: x\nroot: {Tick: {}}\n",
        ["tree.yaml:2:1: error: unknown top-level key 'nmae' (did you mean 'name'?)"],
    ),
    "unknown_attribute": (
        tree("sequence:\n  memroy: true\n  memory: true\n  children: [Tick: {}]"),
        ["tree.yaml:4:5: error: unknown attribute 'memroy' for sequence "
         "(did you mean 'memory'?)"],
    ),
    "unknown_param": (
        tree("Typed: {label: a, bogus: 1}"),
        ["tree.yaml:3:21: error: unknown param 'bogus' for plugin 'Typed' "
         "(expected one of: name, id, count, rate, label, loud, note, source)"],
    ),
    "wrong_type": (
        tree("Typed: {label: 3, loud: 'yes'}"),
        ["tree.yaml:3:18: error: 'label' must be a string, got integer 3",
         "tree.yaml:3:27: error: 'loud' must be a boolean (true or false), got string 'yes'"],
    ),
    "wrong_type_date": (
        tree("Typed: {label: 2024-01-01}"),
        ["tree.yaml:3:18: error: 'label' must be a string, got a date '2024-01-01' "
         "(quote it to make a string)"],
    ),
    "missing_memory": (
        tree("selector:\n  name: Root\n  children: [Tick: {}]"),
        ["tree.yaml:3:3: error: selector 'Root' needs 'memory: true' (resume at the running "
         "child) or 'memory: false' (start again from the first child every tick)"],
    ),
    "missing_required_param": (
        tree("Typed: {}"),
        ["tree.yaml:3:3: error: Typed is missing required param 'label'"],
    ),
    "bad_enum": (
        tree("one_shot:\n  policy: on_complete\n  child: {Tick: {}}"),
        ["tree.yaml:4:13: error: 'policy' must be one of: on_completion, "
         "on_successful_completion; got string 'on_complete' (did you mean 'on_completion'?)"],
    ),
    "out_of_range": (
        tree("sequence:\n  memory: true\n  children:\n"
             "    - Typed: {label: a, count: 101, rate: 0}\n"
             "    - retry: {num_failures: 0, child: {Tick: {}}}\n"
             "    - repeat: {num_success: 0, child: {Tick: {}}}\n"
             "    - timeout: {duration: -1, child: {Tick: {}}}"),
        ["tree.yaml:6:34: error: 'count' must be <= 100, got 101",
         "tree.yaml:6:45: error: 'rate' must be > 0, got 0",
         "tree.yaml:7:31: error: 'num_failures' must be >= 1, got 0",
         "tree.yaml:8:31: error: 'num_success' must not be 0",
         "tree.yaml:9:29: error: 'duration' must be > 0, got -1"],
    ),
    "not_finite": (
        tree("timeout: {duration: .inf, child: {Tick: {}}}"),
        ["tree.yaml:3:23: error: 'duration' must be a finite number, got inf"],
    ),
    "unknown_plugin": (
        tree("sequence:\n  memory: true\n  children:\n    - Tic: {}\n    - Fixd: {}"),
        ["tree.yaml:6:9: error: unknown plugin 'Tic' (did you mean 'Tick'?)",
         "tree.yaml:7:9: error: unknown plugin 'Fixd' (did you mean 'Fixed'?)"],
    ),
    "unsupported_decorator": (
        tree("eternal_guard: {child: {Tick: {}}}"),
        ["tree.yaml:3:3: error: decorator 'eternal_guard' is not supported: needs a Python "
         "callable; use a selector with a condition leaf"],
    ),
    "duplicate_ids": (
        tree("sequence:\n  memory: true\n  children:\n    - Fixed: {id: a}\n"
             "    - Fixed: {id: a}"),
        ["tree.yaml:7:9: error: duplicate id 'a' (first used at tree.yaml:6:9)"],
    ),
    "dangling_reference": (
        tree("sequence:\n  memory: true\n  children:\n    - Fixed: {id: source}\n"
             "    - Typed: {label: a, source: sorce}"),
        ["tree.yaml:7:35: error: 'source' names no leaf: there is no id 'sorce' "
         "(did you mean 'source'?)"],
    ),
    "mistyped_reference": (
        tree("sequence:\n  memory: true\n  children:\n    - Tick: {id: t}\n"
             "    - Typed: {label: a, source: t}"),
        ["tree.yaml:7:35: error: 'source' must name a Fixed leaf, but 't' is a Tick"],
    ),
    "reference_cycle": (
        tree("sequence:\n  memory: true\n  children:\n    - Linked: {id: a, other: b}\n"
             "    - Linked: {id: b, other: a}"),
        ["tree.yaml:7:9: error: reference cycle: 'a' -> 'b' -> 'a'"],
    ),
    "self_reference": (
        tree("Linked: {id: a, other: a}"),
        ["tree.yaml:3:3: error: reference cycle: 'a' -> 'a'"],
    ),
    "decorator_without_child": (
        tree("inverter: {name: Not}"),
        ["tree.yaml:3:3: error: inverter 'Not' needs a 'child' (a decorator has exactly one)"],
    ),
    "decorator_with_children": (
        tree("inverter: {children: [Tick: {}]}"),
        ["tree.yaml:3:3: error: inverter needs a 'child' (a decorator has exactly one)",
         "tree.yaml:3:14: error: unknown attribute 'children' for inverter "
         "(a decorator has exactly one 'child')"],
    ),
    "empty_composite": (
        tree("sequence: {name: Empty, memory: true, children: []}"),
        ["tree.yaml:3:51: error: sequence 'Empty' has no children (a composite needs at least "
         "one)"],
    ),
    "empty_composite_unnamed": (  # regression: 'sequence has no children' named no node
        tree("sequence: {memory: true, children: [{selector: {memory: true, children: []}}]}"),
        ["tree.yaml:3:75: error: selector (child 1 of the root sequence) has no children (a "
         "composite needs at least one)"],
    ),
    "unknown_plugin_with_nothing_close": (  # regression: no hint at plugins: / --plugin-path
        tree("CheckBattery: {}"),
        ["tree.yaml:3:3: error: unknown plugin 'CheckBattery' (if it is a leaf of your own: "
         "install its package (an entry point in group 'sar_framework.plugins'), or name its "
         "module, .py file or folder in the tree's 'plugins:' key or with --plugin-path; see "
         "docs/tutorials/02_writing_a_plugin.md)"],
    ),
    "composite_without_children": (
        tree("sequence: {memory: true}"),
        ["tree.yaml:3:3: error: sequence needs 'children' (a composite has at least one)"],
    ),
    "duplicate_mapping_keys": (
        "format: 1\nroot:\n  Fixed: {status: success, status: failure}\n",
        ["tree.yaml:3:28: error: duplicate key 'status' (first defined on line 3)"],
    ),
    "duplicate_top_level_keys": (
        "format: 1\nroot: {Tick: {}}\nroot: {Tick: {}}\n",
        ["tree.yaml:3:1: error: duplicate key 'root' (first defined on line 2)"],
    ),
    "python_tag": (
        "format: 1\nroot: !!python/object/apply:os.system ['true']\n",
        ["tree.yaml:2:7: error: YAML tag '!!python/object/apply:os.system' is not allowed "
         "(safe YAML only)"],
    ),
    "bad_tagged_scalars": (
        tree("Typed: {label: a, count: !!int x, loud: !!bool maybe, note: !!timestamp q}"),
        ["tree.yaml:3:28: error: YAML: 'x' is not a valid int",
         "tree.yaml:3:43: error: YAML: 'maybe' is not a valid bool",
         "tree.yaml:3:63: error: YAML: 'q' is not a valid timestamp"],
    ),
    "custom_tag": (
        tree("Fixed: {status: !env STATUS}"),
        ["tree.yaml:3:19: error: unsupported YAML tag '!env'"],
    ),
    "alias": (
        "format: 1\nroot:\n  sequence: &s {memory: true, children: [Tick: {}]}\n"
        "subtrees:\n  again: *s\n",
        ["tree.yaml:5:10: error: YAML aliases (*s) are not supported; reuse part of a tree "
         "with a subtree"],
    ),
    "merge_key": (
        tree("Fixed: {<<: {status: failure}}"),
        ["tree.yaml:3:11: error: YAML merge keys (<<) are not supported"],
    ),
    "non_string_key": (
        tree("Fixed: {1: x}"),
        ["tree.yaml:3:11: error: a mapping key must be a string, got int '1'"],
    ),
    "two_keys_in_a_node": (
        tree("Fixed: {}\nname: x"),
        ["tree.yaml:4:3: error: a node has exactly one key, its kind; got 'Fixed', 'name' "
         "(indent the attributes under 'Fixed')"],
    ),
    "empty_node": (
        tree("{}"),
        ["tree.yaml:3:3: error: empty node: expected one key naming the node kind"],
    ),
    "bare_plugin_name": (
        tree("sequence: {memory: true, children: [Tick]}"),
        ["tree.yaml:3:39: error: expected a node: a one-key mapping such as "
         "'NavigateToPose: {}', got string 'Tick' (write 'Tick: {}')"],
    ),
    "null_attributes": (
        "format: 1\nroot:\n  Tick:\n",
        ["tree.yaml:3:8: error: the attributes of 'Tick' must be a mapping, got null "
         "(write 'Tick: {}')"],
    ),
    "missing_format": (
        "root: {Tick: {}}\n",
        ["tree.yaml:1:1: error: missing 'format: 1' (the tree format version)"],
    ),
    "wrong_format": (
        "format: 2\nroot: {Tick: {}}\n",
        ["tree.yaml:1:9: error: 'format' must be one of: 1; got integer 2"],
    ),
    "missing_root": (
        "format: 1\n",
        ["tree.yaml:1:1: error: missing 'root': the node the tree starts from"],
    ),
    "empty_file": (
        "# nothing\n",
        ["tree.yaml:1:1: error: empty file: a tree file needs 'format: 1' and a 'root' node"],
    ),
    "not_a_mapping": (
        "- Tick: {}\n",
        ["tree.yaml:1:1: error: a tree file is a mapping (format, name, root, ...), got a list"],
    ),
    "btcpp_xml": (
        '<root BTCPP_format="4"><BehaviorTree ID="M"><AlwaysSuccess/></BehaviorTree></root>\n',
        ["tree.yaml:1:1: error: a tree file is a mapping (format, name, root, ...), got "
         "BehaviorTree.CPP XML: turn it into a tree file with 'sar-tree import FILE'"],
    ),
    "unknown_subtree": (
        "format: 1\nsubtrees:\n  patrol: {Tick: {}}\nroot: {subtree: patro}\n",
        ["tree.yaml:4:8: error: unknown subtree 'patro' (did you mean 'patrol'?)"],
    ),
    "recursive_subtree": (
        "format: 1\nsubtrees:\n  a: {inverter: {child: {subtree: b}}}\n"
        "  b: {inverter: {child: {subtree: a}}}\nroot: {subtree: a}\n",
        ["tree.yaml:4:26: error: recursive subtree: a -> b -> a"],
    ),
    "unused_recursive_subtree": (
        "format: 1\nsubtrees:\n  a: {inverter: {child: {subtree: b}}}\n"
        "  b: {inverter: {child: {subtree: a}}}\n  loop: {inverter: {child: {subtree: loop}}}\n"
        "root: {Tick: {}}\n",
        ["tree.yaml:4:26: error: recursive subtree: a -> b -> a",
         "tree.yaml:5:29: error: recursive subtree: loop -> loop"],
    ),
    "parallel_selected_required": (
        tree("parallel: {policy: success_on_selected, children: [Tick: {}]}"),
        ["tree.yaml:3:3: error: parallel needs 'selected' when policy is success_on_selected"],
    ),
    "parallel_selected_forbidden": (
        tree("parallel: {policy: success_on_all, selected: [Tick], children: [Tick: {}]}"),
        ["tree.yaml:3:38: error: 'selected' is not allowed unless policy is "
         "success_on_selected"],
    ),
    "parallel_synchronise_forbidden": (
        tree("parallel: {policy: success_on_one, synchronise: true, children: [Tick: {}]}"),
        ["tree.yaml:3:38: error: 'synchronise' is not allowed when policy is success_on_one"],
    ),
    "parallel_selected_unknown_child": (
        tree("parallel:\n  policy: success_on_selected\n  selected: [A, C]\n"
             "  children: [Tick: {name: A}, Tick: {name: B}]"),
        ["tree.yaml:5:19: error: 'selected' names 'C', which is not a child of this parallel"],
    ),
}


@pytest.mark.parametrize("name", sorted(CASES))
def test_error(check: Checker, name: str) -> None:
    text, expected = CASES[name]
    assert check(text) == expected


def test_all_errors_in_one_pass(check: Checker) -> None:
    text = tree(
        "sequence:\n  children:\n    - Tic: {}\n    - Fixed: {id: a, status: bad}\n"
        "    - Fixed: {id: a}\n    - Typed: {label: x, source: zz}\n"
        "    - one_shot: {policy: on_completion}\n    - selector: {memory: false, children: []}"
    )
    assert check(text) == [
        "tree.yaml:3:3: error: sequence needs 'memory: true' (resume at the running child) or "
        "'memory: false' (start again from the first child every tick)",
        "tree.yaml:5:9: error: unknown plugin 'Tic' (did you mean 'Tick'?)",
        "tree.yaml:6:32: error: 'status' must be one of: success, failure, running; got string "
        "'bad'",
        "tree.yaml:7:9: error: duplicate id 'a' (first used at tree.yaml:6:9)",
        "tree.yaml:8:35: error: 'source' names no leaf: there is no id 'zz'",
        "tree.yaml:9:9: error: one_shot needs a 'child' (a decorator has exactly one)",
        "tree.yaml:10:45: error: selector (child 6 of the root sequence) has no children (a "
        "composite needs at least one)",
    ]
