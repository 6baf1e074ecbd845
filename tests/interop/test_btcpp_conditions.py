"""Pre/post-condition attributes on BT.CPP's control nodes, ticked alike by BT.CPP 4.7.3.

``_skipIf``, ``_failureIf`` and ``_onSuccess`` on a Fallback, a Parallel and a Switch2,
whose scripts read an entry SetBlackboard writes (Nav2's RecoveryNode, which the checker
does not have, is covered in tests/engine/nodes/test_control_kinds.py). The exporter does not
write the conditions yet, so they are added to its XML here, on the elements of the same
names.
"""

from __future__ import annotations

import textwrap
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from interop.scripted import run_checker, run_py_trees, scripted_registry
from sar_framework.engine.api import load_spec
from sar_framework.engine.registry import discover
from sar_framework.interop.btcpp_export import export_btcpp

pytestmark = pytest.mark.timeout(600)
GENERIC = Path(__file__).resolve().parents[2] / "tests" / "engine" / "plugins_for_tests" / "generic"

#: node name -> its condition attributes (in the YAML and added to the XML).
CONDITIONS = {
    "Recover": {"_skipIf": "flag == 1"},
    "Both": {"_skipIf": "flag == 0", "_onSuccess": "done := 1"},
    "Choose": {"_failureIf": "flag == 1"},
}

TREE = """\
format: 1
name: t
root:
  Sequence:
    children:
      - IfThenElse:
          children:
            - Tick: {name: Pick}
            - SetBlackboard: {value: "1", output_key: flag}
            - SetBlackboard: {value: "0", output_key: flag}
      - Fallback:
          name: Recover
          children: [Tick: {name: Act}, Tick: {name: Fix}]
      - Parallel:
          name: Both
          children: [Tick: {name: P1}, Tick: {name: P2}]
      - Switch2:
          name: Choose
          variable: "{flag}"
          case_1: "0"
          case_2: "1"
          children: [Tick: {name: Zero}, Tick: {name: One}, Tick: {name: Other}]
"""


def _yaml() -> str:
    text = TREE
    for name, attrs in CONDITIONS.items():
        lines = "".join(f"\n          {k}: \"{v}\"" for k, v in attrs.items())
        text = text.replace(f"name: {name}", f"name: {name}{lines}")
    return text


def _conditions_written(xml: str) -> dict[str, dict[str, str]]:
    """The pre/post-condition attributes of the exported XML, by node name."""
    found: dict[str, dict[str, str]] = {}
    for element in ET.fromstring(xml).iter():
        attrs = {k: v for k, v in element.attrib.items() if k.startswith("_")}
        if attrs:
            found[element.get("name", "")] = attrs
    return found


def test_conditions_on_bt_cpp_controls_tick_as_in_btcpp(btcpp_checker: Path,
                                                        tmp_path: Path) -> None:
    tree = tmp_path / "tree.yaml"
    tree.write_text(_yaml())
    registry = discover([GENERIC], builtins=False, entry_points=False)
    xml = tmp_path / "tree.xml"
    exported = export_btcpp(load_spec(tree, registry=registry), registry)
    assert _conditions_written(exported) == CONDITIONS  # the exporter writes them as given
    xml.write_text(exported)
    script = {"Pick": ["SUCCESS", "FAILURE", "FAILURE", "SUCCESS"], "Act": ["FAILURE", "SUCCESS"],
              "P1": ["RUNNING", "SUCCESS"]}
    ours = run_py_trees(tree, scripted_registry(registry), script, 6, all_ticks=True)
    theirs = run_checker(btcpp_checker, xml, script, 6, all_ticks=True)
    assert theirs == ours
    shown = textwrap.indent("\n".join(ours), "  ")
    assert "visit P1 RUNNING" in shown and "visit Fix SUCCESS" in shown  # both were ticked
    assert "tick 2 FAILURE" in shown  # Choose's _failureIf
