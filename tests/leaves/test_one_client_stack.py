"""Only the leaf toolkit creates action or service clients among the leaves."""

from __future__ import annotations

import ast
from pathlib import Path

PLUGINS = Path(__file__).resolve().parents[2] / "plugins"
CLIENT_MAKERS = {"create_client", "ActionClient"}


def clients_made(path: Path) -> list[str]:
    """Each ``create_client(...)``, ``ActionClient(...)`` or its import, as ``line: what``."""
    found = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Call):
            func = node.func
            name = func.attr if isinstance(func, ast.Attribute) else getattr(func, "id", "")
            if name in CLIENT_MAKERS:
                found.append(f"{node.lineno}: {name}")
        elif (isinstance(node, ast.ImportFrom) and node.module == "rclpy.action"
              and any(alias.name == "ActionClient" for alias in node.names)):
            found.append(f"{node.lineno}: import ActionClient")
    return found


def test_no_leaf_module_makes_its_own_client() -> None:
    modules = sorted(PLUGINS.rglob("*.py"))
    assert len(modules) > 20  # the scan sees the built-in leaves
    made = [f"{path.relative_to(PLUGINS.parent)}:{where}"
            for path in modules for where in clients_made(path)]
    assert made == [], "use sar_framework.leaves (ActionLeaf, ServiceLeaf, PolledGoal, " \
                       "GoalBatch, PolledServiceCall, TickServiceCall):\n" + "\n".join(made)


def test_the_scan_finds_a_client(tmp_path: Path) -> None:
    text = (PLUGINS / "nav2" / "behaviors.py").read_text(encoding="utf-8")
    probe = tmp_path / "probe.py"
    probe.write_text(text + "\n\ndef f(node):\n    node.create_client(1, 'x')\n"
                     "    from rclpy.action import ActionClient\n    ActionClient(node, 1, 'y')\n",
                     encoding="utf-8")
    assert sorted(where.split(": ")[1] for where in clients_made(probe)) == [
        "ActionClient", "create_client", "import ActionClient"]
