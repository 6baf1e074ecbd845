"""Apps: which a tree uses, what each adds, and a tree that uses none (no ROS here)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest
from sar_plugins.sar.app import APP as SAR

from sar_framework.app import App, AppError, apps_for, discover_apps, tree_apps
from sar_framework.engine.api import validate
from sar_framework.mission.processes import MissionSettings, mission_processes
from sar_framework.orchestrate.config import check_config
from sar_framework.orchestrate.options import RunConfig, RunUsageError

REPO = Path(__file__).resolve().parents[2]
SAR_TREE = REPO / "trees" / "search_and_rescue.yaml"
APP_LESS = """\
format: 1
name: patrol
root:
  sequence:
    name: Patrol
    memory: true
    children:
      - Wait: {wait_duration: 1.0}
      - Script: {code: "laps := 1"}
"""
SHELF_APP = '''\
import py_trees
from py_trees.common import Status

from sar_framework.app import App, AppRun
from sar_framework.engine.plugin import leaf


@leaf(context=["shelves"])
class ScanShelf(py_trees.behaviour.Behaviour):
    """Scan the next shelf."""

    def __init__(self, name, *, shelves):
        super().__init__(name=name)
        self.shelves = shelves

    def update(self):
        return Status.SUCCESS


APP = App(name="shelves", provides=("shelves",),
          start=lambda node, source, locations: AppRun({"shelves": ["nw", "ne"]}))
'''


def test_search_and_rescue_is_an_installed_app() -> None:
    assert SAR in discover_apps()
    assert SAR.provides == ("zone_manager",)


def test_the_reference_tree_uses_the_search_and_rescue_app() -> None:
    assert tree_apps(SAR_TREE) == [SAR]


def test_a_tree_of_nav2_leaves_and_scripts_uses_no_app(tmp_path: Path) -> None:
    tree = tmp_path / "patrol.yaml"
    tree.write_text(APP_LESS, encoding="utf-8")
    assert validate(tree).spec is not None
    assert tree_apps(tree) == []


def test_an_app_in_the_trees_plugins_is_found_there(tmp_path: Path) -> None:
    (tmp_path / "shelves.py").write_text(SHELF_APP, encoding="utf-8")
    tree = tmp_path / "scan.yaml"
    tree.write_text("format: 1\nname: scan\nplugins: [shelves.py]\nroot:\n  ScanShelf: {}\n",
                    encoding="utf-8")
    assert [app.name for app in tree_apps(tree)] == ["shelves"]


def test_two_apps_providing_one_object_are_refused(tmp_path: Path,
                                                   monkeypatch: pytest.MonkeyPatch) -> None:
    twin = App(name="twin", provides=("zone_manager",))
    monkeypatch.setattr("sar_framework.app.discovery._installed", [SAR, twin])
    result = validate(SAR_TREE)
    with pytest.raises(AppError, match=r"zone_manager.*search_and_rescue, twin"):
        apps_for(result.spec, result.registry)


def test_only_a_tree_using_the_app_starts_its_servers() -> None:
    settings = MissionSettings(tree="t.yaml")
    assert [p.label for p in mission_processes(settings)] == ["sim", "runner"]
    assert [p.label for p in mission_processes(settings, [SAR])] == [
        "sim", "detect", "report", "runner"]


def test_sar_tree_run_needs_no_parameter_file_for_a_tree_without_an_app(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)  # a folder of the user's own: no config/ here
    Path("patrol.yaml").write_text(APP_LESS, encoding="utf-8")
    config = RunConfig(tree="patrol.yaml")
    inputs = check_config(config)
    assert (inputs.apps, inputs.params_file, config.params) == ((), "", "")


def test_a_tree_using_the_app_gets_its_parameter_file_from_any_folder(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    config = RunConfig(tree=str(SAR_TREE))
    inputs = check_config(config)
    assert inputs.apps == (SAR,)
    assert config.params == str(REPO / "config" / "mission_params.yaml")
    assert set(inputs.places) == {"zone_a", "zone_b", "zone_c", "zone_d"}


def test_the_apps_checks_still_apply_to_a_file_without_zones(tmp_path: Path) -> None:
    params = tmp_path / "params.yaml"
    params.write_text("/**:\n  ros__parameters:\n    tick_rate_hz: 2.0\n", encoding="utf-8")
    with pytest.raises(RunUsageError, match="zone_order: missing"):
        check_config(RunConfig(tree=str(SAR_TREE), params=str(params)))
    app_less = tmp_path / "patrol.yaml"
    app_less.write_text(APP_LESS, encoding="utf-8")
    assert check_config(RunConfig(tree=str(app_less), params=str(params))).apps == ()


def test_the_app_less_checks_import_no_ros() -> None:
    code = ("import sys, sar_framework.app, sar_plugins.sar.app\n"
            "print(sorted(m for m in sys.modules if m.split('.')[0] in ('rclpy',)))")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          check=False, timeout=60)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "[]"


def test_the_watch_header_shows_the_zone_only_for_a_tree_that_has_one() -> None:
    from sar_framework.watch.view import header

    app_less = {"tree": "patrol", "tick": 3, "sim_s": 1.5, "status": "RUNNING"}
    assert "zone" not in header(app_less, 2.0).plain
    with_zone = {**app_less, "zone": {"id": "zone_b", "index": 1, "total": 4}}
    assert "zone zone_b (2/4)" in header(with_zone, 2.0).plain
    assert "zone none left" in header({**app_less, "zone": None}, 2.0).plain
