"""Plugin discovery: local files and dirs, module names, entry points, and its diagnostics."""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from sar_framework.engine.registry import ENTRY_POINT_GROUP, Registry, discover

from .conftest import GENERIC_PLUGINS, VENV_BIN, write

PLUGIN = """
import py_trees
from sar_framework.engine.plugin import Param, leaf

@leaf(params=[Param("speed", float, default=1.0)])
class {name}(py_trees.behaviour.Behaviour):
    \"\"\"A test leaf.\"\"\"

    def __init__(self, name, *, speed):
        super().__init__(name)
"""


def messages(registry: object) -> list[str]:
    return [str(d) for d in registry.diagnostics]  # type: ignore[attr-defined]


def test_directory_of_plugins() -> None:
    reg = discover([GENERIC_PLUGINS], builtins=False, entry_points=False)
    assert reg.names() == ["Exploding", "Fixed", "Linked", "Tick", "Typed"]
    assert reg.get("Typed").source.endswith("generic/plugins.py")  # type: ignore[union-attr]
    assert messages(reg) == []


def test_single_file_and_relative_base(tmp_path: Path) -> None:
    write(tmp_path, "one.py", PLUGIN.format(name="One"))
    reg = discover(["one.py"], builtins=False, entry_points=False, base=tmp_path)
    assert reg.names() == ["One"]


#: (file written, its text, the path discovered, the one diagnostic expected); the file's
#: leaves are not registered, except where only a reference is wrong (``refs.py``).
BAD_PLUGIN_FILES = {
    "a syntax error points into the file": (
        "p/bad.py", "x = (\n", "p/bad.py",
        "p/bad.py:1:5: error: cannot import plugin file 'p/bad.py': SyntaxError: '(' was never "
        "closed"),
    "a runtime error points at the raising line": (
        "p/bad.py", "import os\n\nraise RuntimeError('no ROS here')\n", "p",
        "p/bad.py:3:1: error: cannot import plugin file 'p/bad.py': RuntimeError: no ROS here"),
    "sys.exit in a plugin is a diagnostic": (
        "quits.py", "import sys\nsys.exit(3)\n", "quits.py",
        "quits.py:2:1: error: cannot import plugin file 'quits.py': SystemExit: 3"),
    "a reserved name": (
        "r.py", PLUGIN.format(name="sequence"), "r.py",
        "r.py:4:1: error: plugin name 'sequence' is reserved (from r.py)"),
    "a leaf that is not a behaviour is reported at its class": (
        "plain.py", "from sar_framework.engine.plugin import leaf\n\n\n"
        "@leaf()\nclass Plain:\n    \"\"\"Not a behaviour.\"\"\"\n", "plain.py",
        "plain.py:4:1: error: plugin 'Plain' is not a py_trees behaviour (from plain.py)"),
    "an unknown reference type": (
        "refs.py", textwrap.dedent("""
            import py_trees
            from sar_framework.engine.plugin import Param, leaf

            @leaf(params=[Param("target", ref="Nowhere")])
            class Refers(py_trees.behaviour.Behaviour):
                def __init__(self, name, *, target):
                    super().__init__(name)
        """), "refs.py",
        "refs.py:4:1: error: param 'target' of plugin 'Refers' refers to unknown plugin "
        "'Nowhere'"),
}


@pytest.mark.parametrize("case", BAD_PLUGIN_FILES.values(), ids=BAD_PLUGIN_FILES.keys())
def test_a_bad_plugin_file_is_one_located_diagnostic(
    case: tuple[str, str, str, str], tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    name, text, discovered, message = case
    monkeypatch.chdir(tmp_path)
    write(tmp_path, name, text)
    reg = discover([discovered], builtins=False, entry_points=False)
    assert reg.names() == (["Refers"] if name == "refs.py" else [])
    assert messages(reg) == [message]


def test_two_plugins_with_one_name(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    write(tmp_path, "a/one.py", PLUGIN.format(name="Same"))
    write(tmp_path, "b/two.py", PLUGIN.format(name="Same"))
    reg = discover(["a", "b"], builtins=False, entry_points=False)
    assert messages(reg) == [
        "b/two.py:4:1: error: plugin 'Same' is defined twice: in a/one.py and in b/two.py"
    ]
    assert reg.get("Same").source == "a/one.py"  # type: ignore[union-attr]


def test_subclass_is_not_the_same_plugin(tmp_path: Path) -> None:
    write(tmp_path, "sub.py", PLUGIN.format(name="Base") + textwrap.dedent("""
        class Derived(Base):
            pass
    """))
    reg = discover([tmp_path / "sub.py"], builtins=False, entry_points=False)
    assert reg.names() == ["Base"]


def test_missing_path(tmp_path: Path) -> None:
    reg = discover(["nowhere/x.py"], builtins=False, entry_points=False, base=tmp_path)
    assert messages(reg) == ["nowhere/x.py:1:1: error: plugin path 'nowhere/x.py' does not exist"]


def test_module_name_and_package(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    write(tmp_path, "sar_test_pkg_a/__init__.py", "")
    write(tmp_path, "sar_test_pkg_a/leaf_one.py", PLUGIN.format(name="PkgOne"))
    write(tmp_path, "sar_test_pkg_a/leaf_two.py", PLUGIN.format(name="PkgTwo"))
    monkeypatch.syspath_prepend(str(tmp_path))
    reg = discover(["sar_test_pkg_a"], builtins=False, entry_points=False, base=tmp_path / "x")
    assert reg.names() == ["PkgOne", "PkgTwo"]
    assert reg.get("PkgOne").source.startswith("sar_test_pkg_a.leaf_one (")  # type: ignore


def test_missing_module_name(tmp_path: Path) -> None:
    reg = discover(["sar_no_such_module_xyz"], builtins=False, entry_points=False, base=tmp_path)
    assert messages(reg) == [
        "sar_no_such_module_xyz:1:1: error: cannot import plugin module 'sar_no_such_module_xyz':"
        " ModuleNotFoundError: No module named 'sar_no_such_module_xyz'"
    ]


def test_entry_points(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    write(tmp_path, "sar_ep_plugins.py", PLUGIN.format(name="FromEntryPoint"))
    write(tmp_path, "sar_ep_single.py", PLUGIN.format(name="SingleClass"))
    dist = tmp_path / "sar_ep_demo-1.0.dist-info"
    write(dist, "METADATA", "Metadata-Version: 2.1\nName: sar-ep-demo\nVersion: 1.0\n")
    write(dist, "entry_points.txt", "[sar_framework.plugins]\nmodule = sar_ep_plugins\n"
          "single = sar_ep_single:SingleClass\nbroken = sar_ep_missing_mod\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    reg = discover(builtins=False, entry_points=True)
    assert {"FromEntryPoint", "SingleClass"} <= set(reg.names())
    assert reg.get("SingleClass").source == (  # type: ignore[union-attr]
        "entry point 'single = sar_ep_single:SingleClass' (sar-ep-demo)"
    )
    assert [m for m in messages(reg) if "sar_ep_missing_mod" in m] == [
        "sar_ep_missing_mod:1:1: error: cannot import plugin module 'sar_ep_missing_mod': "
        "ModuleNotFoundError: No module named 'sar_ep_missing_mod'"
    ]


def test_builtins_import_without_errors() -> None:
    reg = discover(entry_points=False)
    assert messages(reg) == []
    assert "sar_plugins" in sys.modules


@pytest.mark.parametrize("order", ["package first", "path first"])
def test_one_module_reached_as_package_and_by_path_is_one_plugin(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, order: str
) -> None:
    monkeypatch.chdir(tmp_path)
    package = "sar_test_pkg_same_" + order.split(maxsplit=1)[0]
    write(tmp_path, f"site/{package}/__init__.py", "")
    write(tmp_path, f"site/{package}/leaves.py", PLUGIN.format(name="Installed"))
    monkeypatch.syspath_prepend(str(tmp_path / "site"))
    entries = [package, f"site/{package}/leaves.py"]
    if order == "path first":
        entries.reverse()
    reg = discover(entries, builtins=False, entry_points=False)
    assert messages(reg) == []
    assert reg.names() == ["Installed"]


def test_a_different_definition_of_an_installed_name_names_both(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(tmp_path)
    write(tmp_path, "site/sar_test_pkg_clash/__init__.py", "")
    write(tmp_path, "site/sar_test_pkg_clash/leaves.py", PLUGIN.format(name="Clash"))
    write(tmp_path, "local/clash.py", PLUGIN.format(name="Clash"))
    monkeypatch.syspath_prepend(str(tmp_path / "site"))
    reg = discover(["sar_test_pkg_clash", "local/clash.py"], builtins=False, entry_points=False)
    assert messages(reg) == [
        "local/clash.py:4:1: error: plugin 'Clash' is defined twice: in "
        "sar_test_pkg_clash.leaves (site/sar_test_pkg_clash/leaves.py) and in local/clash.py"
    ]


def test_validate_imports_installed_plugins_and_reports_their_failures(tmp_path: Path) -> None:
    site = tmp_path / "site"
    dist = site / "sar_installed-1.0.dist-info"
    write(dist, "METADATA", "Metadata-Version: 2.1\nName: sar_installed\nVersion: 1.0\n")
    write(dist, "entry_points.txt", f"[{ENTRY_POINT_GROUP}]\ngood = sar_installed_good\n"
          "broken = sar_installed_broken\n")
    write(site, "sar_installed_good.py", PLUGIN.format(name="FromSite"))
    write(site, "sar_installed_broken.py", "X = 1\n\nraise RuntimeError('no hardware')\n")
    write(tmp_path, "tree.yaml", "format: 1\nroot: {FromSite: {}}\n")
    code = ("import sys\nfrom sar_framework.cli import main\n"
            "code = main(['validate', 'tree.yaml'])\n"
            "print(sys.modules['sar_installed_good'].FromSite.__name__)\nsys.exit(code)\n")
    path = os.pathsep.join(p for p in (str(site), os.environ.get("PYTHONPATH", "")) if p)
    run = subprocess.run([str(VENV_BIN / "python"), "-c", code], capture_output=True, text=True,
                         cwd=tmp_path, env=dict(os.environ, PYTHONPATH=path), check=False,
                         timeout=120)
    assert run.returncode == 1, run.stderr
    assert run.stderr.splitlines() == [
        "site/sar_installed_broken.py:3:1: error: cannot import plugin module "
        "'sar_installed_broken': RuntimeError: no hardware",
        "1 error",
    ]
    assert run.stdout.splitlines()[-1] == "FromSite"  # imported, not read


def test_a_constructor_that_repeats_a_default_or_misses_a_name_is_a_warning(tmp_path) -> None:
    """Plugins written before defaults lived only in @leaf keep working, with a warning."""
    path = write(tmp_path, "old.py", """
        import py_trees
        from sar_framework.engine.plugin import Param, leaf

        @leaf(params=[Param("speed", float, default=1.0), Param("lane", int, default=0)])
        class Old(py_trees.behaviour.Behaviour):
            def __init__(self, name, *, speed=1.0):
                super().__init__(name)
    """)
    registry = Registry()
    registry.import_path(str(path), tmp_path)
    assert [d.severity for d in registry.diagnostics] == ["warning", "warning"]
    assert [str(d).split(": warning: ")[1] for d in registry.diagnostics] == [
        "plugin 'Old': __init__ repeats a default for 'speed' (1.0); the @leaf declaration "
        "is where defaults live",
        "plugin 'Old': __init__ does not take the declared 'lane'",
    ]
    where = str(registry.diagnostics[0]).split(": warning: ")[0]
    assert where.endswith("old.py:4:1"), where  # the file and the class's line
    assert registry.get("Old") is not None  # registered all the same
