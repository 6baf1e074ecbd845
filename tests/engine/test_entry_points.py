"""The entry-point pre-check: found where importlib.metadata finds one, unsure means ask it."""

from __future__ import annotations

import importlib.metadata
import os
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

from sar_framework.engine.entry_points import declared_anywhere
from sar_framework.engine.registry import ENTRY_POINT_GROUP

from .conftest import REPO, VENV_BIN, write

PLUGIN = """
import py_trees
from sar_framework.engine.plugin import leaf

@leaf()
class {name}(py_trees.behaviour.Behaviour):
    \"\"\"A leaf from an installed package.\"\"\"
"""


def site_with(tmp_path: Path, dist: str, entry_points: str) -> Path:
    """A site directory holding one distribution's metadata with ``entry_points``."""
    site = tmp_path / "site"
    write(site / f"{dist}-1.0.dist-info", "METADATA",
          f"Metadata-Version: 2.1\nName: {dist}\nVersion: 1.0\n")
    write(site / f"{dist}-1.0.dist-info", "entry_points.txt", entry_points)
    return site


def test_a_declaration_in_a_site_directory_is_found(tmp_path: Path) -> None:
    site = site_with(tmp_path, "sar_found", f"[{ENTRY_POINT_GROUP}]\nx = sar_found_mod\n")
    write(site / "other-1.0.dist-info", "entry_points.txt", "[console_scripts]\no = m:f\n")
    assert declared_anywhere(ENTRY_POINT_GROUP, [str(site)])
    assert not declared_anywhere("some.other.group", [str(site)])
    # An egg-info folder (setup.py develop) counts as importlib.metadata counts it.
    (site / "sar_found-1.0.dist-info").rename(site / "sar_found.egg-info")
    assert declared_anywhere(ENTRY_POINT_GROUP, [str(site)])


def test_no_declaration_anywhere_is_false(tmp_path: Path) -> None:
    site = site_with(tmp_path, "sar_plain", "[console_scripts]\nsar-plain = m:f\n")
    write(site, "legacy.egg-info", "Metadata-Version: 1.0\nName: legacy\n")  # a PKG-INFO file
    write(site / "bare-1.0.dist-info", "METADATA", "Name: bare\n")  # no entry_points.txt
    assert not declared_anywhere(ENTRY_POINT_GROUP, [str(site), str(tmp_path / "missing")])


def test_agrees_with_importlib_metadata_on_this_install() -> None:
    groups = set(importlib.metadata.entry_points().groups)
    assert groups  # console_scripts at least: the comparison below is not empty
    for group in groups:
        assert declared_anywhere(group), group
    assert bool(importlib.metadata.entry_points(group=ENTRY_POINT_GROUP)) == \
        declared_anywhere(ENTRY_POINT_GROUP)
    assert not declared_anywhere("sar_no_such_group_xyz")


def test_places_it_cannot_read_like_importlib_metadata_ask_importlib_metadata(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    archive = tmp_path / "plugins.zip"
    with zipfile.ZipFile(archive, "w") as zipped:
        zipped.writestr("z-1.0.dist-info/entry_points.txt", "[console_scripts]\nz = m:f\n")
    assert declared_anywhere(ENTRY_POINT_GROUP, [str(archive)])
    (tmp_path / "old.egg" / "EGG-INFO").mkdir(parents=True)
    assert declared_anywhere(ENTRY_POINT_GROUP, [str(tmp_path / "old.egg")])

    class OwnDistributions:
        """A meta-path finder with distributions of its own, as importlib.metadata allows."""

        def find_spec(self, *args: object) -> None:
            return None

        def find_distributions(self, *args: object) -> list[object]:
            return []

    empty = tmp_path / "empty"
    empty.mkdir()
    assert not declared_anywhere(ENTRY_POINT_GROUP, [str(empty)])
    monkeypatch.setattr(sys, "meta_path", [OwnDistributions(), *sys.meta_path])
    assert declared_anywhere(ENTRY_POINT_GROUP, [str(empty)])


def run_validate(cwd: Path, *args: str, pythonpath: Path | None = None,
                 script: str = "") -> subprocess.CompletedProcess[str]:
    """``sar-tree validate`` in a fresh interpreter, then ``script`` (which may print)."""
    env = dict(os.environ)
    if pythonpath is not None:
        env["PYTHONPATH"] = str(pythonpath)
    code = ("import sys\nfrom sar_framework.cli import main\n"
            f"code = main(['validate', *{list(args)!r}])\n{script}\nsys.exit(code)\n")
    return subprocess.run([str(VENV_BIN / "python"), "-c", code], capture_output=True,
                          text=True, cwd=cwd, env=env, check=False, timeout=120)


def test_validate_without_declarations_does_not_import_importlib_metadata() -> None:
    assert not declared_anywhere(ENTRY_POINT_GROUP), "an installed package declares plugins"
    run = run_validate(REPO, "-q", "trees/search_and_rescue.yaml",
                       script="print('importlib.metadata' in sys.modules)")
    assert run.returncode == 0, run.stderr
    assert run.stdout == "False\n"


def test_validate_imports_installed_plugins_and_reports_their_failures(tmp_path: Path) -> None:
    site = site_with(tmp_path, "sar_installed",
                     f"[{ENTRY_POINT_GROUP}]\ngood = sar_installed_good\n"
                     "broken = sar_installed_broken\n")
    write(site, "sar_installed_good.py", PLUGIN.format(name="FromSite"))
    write(site, "sar_installed_broken.py", "X = 1\n\nraise RuntimeError('no hardware')\n")
    write(tmp_path, "tree.yaml", "format: 1\nroot: {FromSite: {}}\n")
    run = run_validate(tmp_path, "tree.yaml", pythonpath=site,
                       script="print(sys.modules['sar_installed_good'].FromSite.__name__)")
    assert run.returncode == 1, run.stderr
    assert run.stderr.splitlines() == [
        "site/sar_installed_broken.py:3:1: error: cannot import plugin module "
        "'sar_installed_broken': RuntimeError: no hardware",
        "1 error",
    ]
    assert run.stdout.splitlines()[-1] == "FromSite"  # imported, not read
