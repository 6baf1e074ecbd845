"""docs/reference/parameters.md and the other places showing a node's parameters agree with it."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

from sar_framework.orchestrate.inputs import node_parameters
from sar_framework.orchestrate.parameter_docs import default_text, document, markdown_table
from sar_framework.sim.params import SPEED

REPO = Path(__file__).resolve().parents[2]
DOC = REPO / "docs" / "reference" / "parameters.md"
TABLE_MODULES = ("sar_framework.mission.runner_params", "sar_framework.sim.params",
                 "sar_plugins.sar.servers.params", "sar_framework.recording.params",
                 "sar_framework.orchestrate.inputs", "sar_framework.orchestrate.parameter_docs")


def test_docs_parameters_md_is_generated_from_the_tables() -> None:
    assert DOC.read_text() == document(), (
        "docs/reference/parameters.md is stale: python -m sar_framework.orchestrate.parameter_docs "
        "> docs/reference/parameters.md")


def test_a_changed_table_shows_in_the_docs() -> None:
    """The comparison above can fail: a different default is a different table."""
    sim = node_parameters()["sim"]
    changed = tuple(p if p is not SPEED else type(p)(**{**p.__dict__, "default": 7.0})
                    for p in sim)
    assert markdown_table(changed) != markdown_table(sim)
    assert markdown_table(sim) in DOC.read_text()


def test_launch_arguments_table_gives_the_tables_speed() -> None:
    row = next(line for line in (REPO / "docs" / "reference" / "cli.md").read_text().splitlines()
               if line.startswith("| `speed` |"))
    assert row.split("|")[2].strip() == f"`{SPEED.default!r}`"


def test_every_table_module_imports_no_ros() -> None:
    code = ("import sys\n" + "".join(f"import {m}\n" for m in TABLE_MODULES)
            + "print(sorted(m for m in sys.modules if m.split('.')[0] in "
              "('rclpy', 'rcl_interfaces', 'nav2_msgs', 'sar_interfaces', "
              "'sar_fleet_interfaces', 'launch')))")
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                            cwd=REPO, timeout=60, check=True)
    assert result.stdout.strip() == "[]"


def test_sar_sim_help_lists_every_simulator_parameter() -> None:
    from sar_framework.sim.__main__ import usage

    text = usage()
    for param in node_parameters()["sim"]:
        assert re.search(rf"^  {re.escape(param.name)} ", text, re.M), param.name
        assert param.description in text
    assert "  speed                float     20.0\n" in text


def test_defaults_as_the_docs_show_them() -> None:
    from sar_plugins.sar.params import MISSION_PARAMETERS

    by_name = {p.name: p for p in (*MISSION_PARAMETERS, *node_parameters()["runner"])}
    assert [default_text(by_name[n]) for n in ("zone_order", "seed_amcl", "tree",
                                                "tick_rate_hz")] == [
        "(required)", "`true`", "`'trees/search_and_rescue.yaml'`", "`2.0`"]
    assert "/work/" not in DOC.read_text() and str(REPO) not in DOC.read_text()
