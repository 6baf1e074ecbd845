"""The README fits on one screen and what it shows is true: its tree validates, its links
resolve, its two commands are the Makefile's and CI's. And the launch arguments reference
lists every argument the launch file declares."""

from __future__ import annotations

import re
from pathlib import Path

from sar_framework.engine.api import validate

REPO = Path(__file__).resolve().parents[2]
README = REPO / "README.md"
YAML_BLOCK = re.compile(r"^```yaml\n(.*?)^```", re.MULTILINE | re.DOTALL)
LINK = re.compile(r"\]\(([^)#\s]+)(?:#[^)]*)?\)")


def test_the_readme_fits_on_one_screen() -> None:
    assert len(README.read_text().splitlines()) <= 60


def test_the_readme_tree_has_eight_lines_and_validates(tmp_path: Path) -> None:
    blocks = YAML_BLOCK.findall(README.read_text())
    assert len(blocks) == 1, "the README shows one tree"
    assert len(blocks[0].splitlines()) == 8
    tree = tmp_path / "readme_tree.yaml"
    tree.write_text(blocks[0])
    result = validate(tree)
    assert [str(d) for d in result.diagnostics] == []


def test_the_readme_links_resolve() -> None:
    links = [link for link in LINK.findall(README.read_text()) if "://" not in link]
    assert len(links) >= 8
    missing = [link for link in links if not (REPO / link).exists()]
    assert missing == []


def test_the_two_commands_are_make_targets_and_ci_runs_the_tests() -> None:
    text = README.read_text()
    assert "make run " in text and "make test " in text
    makefile = (REPO / "Makefile").read_text()
    assert re.search(r"^run: ", makefile, re.M) and re.search(r"^test: ", makefile, re.M)
    assert "exec make test" in (REPO / ".ci" / "run").read_text()


def test_every_launch_argument_is_in_the_reference() -> None:
    declared = [name for launch in ("tree.launch.py", "search_and_rescue.launch.py")
                for name in re.findall(r'DeclareLaunchArgument\("(\w+)"',
                                       (REPO / "launch" / launch).read_text())]
    assert len(declared) >= 10
    table = re.findall(r"^\| `(\w+)` \| ", (REPO / "docs" / "reference" / "cli.md").read_text(),
                       re.M)
    assert [name for name in declared if name not in table] == []
