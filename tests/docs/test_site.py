"""The docs site builds with Sphinx, every warning (a broken link, a bad reference) an error.

The build runs in a child process (Sphinx imports the API modules for autodoc) into a
temporary folder; nothing is fetched from the network.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
DOCS = REPO / "docs"


def build(source: Path, out: Path) -> subprocess.CompletedProcess[str]:
    """Build ``source`` into ``out`` as HTML: warnings are errors, all of them reported."""
    return subprocess.run(
        [sys.executable, "-m", "sphinx", "-q", "-W", "--keep-going", "-n", "-E",
         "-b", "html", "-d", str(out / "doctrees"), str(source), str(out / "html")],
        cwd=REPO, capture_output=True, text=True, timeout=300, check=False)


def test_the_site_builds_without_warnings(tmp_path: Path) -> None:
    done = build(DOCS, tmp_path)
    assert done.returncode == 0, f"sphinx-build exit {done.returncode}:\n{done.stderr}"
    assert done.stderr == ""
    html = tmp_path / "html"
    for page in ("index", "tutorials/README", "how-to/index", "reference/index",
                 "explanation/index", "reference/api", "architecture"):
        assert (html / f"{page}.html").is_file(), page
    api = (html / "reference" / "api.html").read_text()
    for name in ("sar_framework.engine.api.load_tree", "sar_framework.engine.plugin.PluginSpec",
                 "sar_framework.testing.assert_statuses", "sar_framework.leaves.ActionLeaf",
                 "sar_framework.leaves.ActionLeaf.set_goal", "sar_framework.leaves.ServiceLeaf",
                 "sar_framework.leaves.TopicCondition", "sar_framework.leaves.StatefulLeaf"):
        assert f'id="{name}"' in api, f"the API reference does not document {name}"


def test_every_page_is_in_the_site(tmp_path: Path) -> None:
    """A page no toctree lists is a warning, so the test above fails for it; check it can."""
    source = tmp_path / "src"
    source.mkdir()
    (source / "conf.py").write_text("extensions = ['myst_parser']\n")
    (source / "index.md").write_text("# Home\n\nSee [a missing page](missing.md).\n")
    (source / "orphan.md").write_text("# Listed nowhere\n")
    done = build(source, tmp_path / "out")
    assert done.returncode != 0
    assert "missing.md" in done.stderr and "orphan" in done.stderr, done.stderr
