"""``sar-tree``: exit codes 0/1/2 through the installed script, never a traceback."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from .conftest import FIXTURES, GENERIC_PLUGINS, REPO, VENV_BIN, write

SAR_TREE = str(VENV_BIN / "sar-tree")
GOOD = "format: 1\nname: demo\nroot:\n  retry:\n    num_failures: 3\n    child: {Fixed: {}}\n"
BAD = "format: 1\nroot:\n  sequence:\n    children: [Fixd: {}]\n"


def sar_tree(*args: str, cwd: Path = REPO) -> subprocess.CompletedProcess[str]:
    return subprocess.run([SAR_TREE, *args], capture_output=True, text=True, cwd=cwd,
                          check=False, timeout=120)


def no_traceback(run: subprocess.CompletedProcess[str]) -> None:
    assert "Traceback" not in run.stderr and "Traceback" not in run.stdout


def test_validate_clean_exits_0(tmp_path: Path) -> None:
    write(tmp_path, "good.yaml", GOOD)
    run = sar_tree("validate", "good.yaml", "--plugin-path", str(GENERIC_PLUGINS), cwd=tmp_path)
    assert run.returncode == 0, run.stderr
    assert run.stdout == "good.yaml: ok (2 nodes; completion: end)\n"
    assert run.stderr == ""
    no_traceback(run)


def test_validate_errors_exit_1_gcc_style(tmp_path: Path) -> None:
    write(tmp_path, "bad.yaml", BAD)
    run = sar_tree("validate", "bad.yaml", "--plugin-path", str(GENERIC_PLUGINS), cwd=tmp_path)
    assert run.returncode == 1
    assert run.stderr.splitlines() == [
        "bad.yaml:3:3: error: sequence needs 'memory: true' (resume at the running child) or "
        "'memory: false' (start again from the first child every tick)",
        "bad.yaml:4:16: error: unknown plugin 'Fixd' (did you mean 'Fixed'?)",
        "2 errors",
    ]
    no_traceback(run)


def test_validate_several_files(tmp_path: Path) -> None:
    write(tmp_path, "good.yaml", GOOD)
    write(tmp_path, "bad.yaml", BAD)
    run = sar_tree("validate", "good.yaml", "bad.yaml", "--plugin-path", str(GENERIC_PLUGINS),
                   cwd=tmp_path)
    assert run.returncode == 1
    assert "good.yaml: ok" in run.stdout
    assert "bad.yaml:4:16: error: unknown plugin 'Fixd'" in run.stderr


@pytest.mark.parametrize(
    "args",
    [[], ["validate"], ["validate", "missing.yaml"], ["frobnicate"], ["validate", "--bogus", "x"],
     ["render", "good.yaml", "-o", "out.svg", "--format", "ascii"], ["--debug", "validate"]],
)
def test_usage_errors_exit_2(tmp_path: Path, args: list[str]) -> None:
    write(tmp_path, "good.yaml", GOOD)
    run = sar_tree(*args, cwd=tmp_path)
    assert run.returncode == 2, run.stderr
    assert run.stderr
    no_traceback(run)


def test_an_unknown_subcommand_lists_every_subcommand(tmp_path: Path) -> None:
    run = sar_tree("--debug", "frobnicate", cwd=tmp_path)
    assert run.returncode == 2
    assert "invalid choice: 'frobnicate' (choose from 'validate', 'render', 'plugins'" in run.stderr


def test_validate_directory_is_usage_error(tmp_path: Path) -> None:
    run = sar_tree("validate", str(tmp_path))
    assert run.returncode == 2
    assert "not a file" in run.stderr


def test_python_m_entry_point(tmp_path: Path) -> None:
    write(tmp_path, "bad.yaml", BAD)
    run = subprocess.run([sys.executable, "-m", "sar_framework", "validate", "bad.yaml",
                          "--plugin-path", str(GENERIC_PLUGINS)], capture_output=True, text=True,
                         cwd=tmp_path, check=False)
    assert run.returncode == 1
    assert "bad.yaml:4:16: error" in run.stderr


def test_broken_plugin_module_is_a_diagnostic(tmp_path: Path) -> None:
    write(tmp_path, "plugins/broken.py", "import nonexistent_module_xyz\n")
    write(tmp_path, "tree.yaml", "format: 1\nplugins: [plugins]\nroot: {Tick: {}}\n")
    run = sar_tree("validate", "tree.yaml", cwd=tmp_path)
    assert run.returncode == 1
    assert run.stderr.splitlines()[0] == (
        "tree.yaml:2:11: error: cannot import plugin file 'plugins/broken.py': "
        "ModuleNotFoundError: No module named 'nonexistent_module_xyz' "
        "(at plugins/broken.py:1:1)"
    )
    no_traceback(run)


def test_plugins_lists_params(tmp_path: Path) -> None:
    run = sar_tree("plugins", "--plugin-path", str(GENERIC_PLUGINS), cwd=tmp_path)
    assert run.returncode == 0, run.stderr
    assert "Typed  [" in run.stdout
    assert "- count: int = 1 [>= 0; <= 100]  How many." in run.stdout
    assert "- source: ref Fixed = None  An optional Fixed leaf." in run.stdout


def test_plugins_kinds_lists_every_node_kind(tmp_path: Path) -> None:
    from sar_framework.engine.nodes.node_kinds import KINDS
    from sar_framework.engine.registry import default_registry

    run = sar_tree("plugins", "--kinds", cwd=tmp_path)
    assert run.returncode == 0, run.stderr
    listed = [line.split("  [")[0] for line in run.stdout.splitlines() if "  [" in line]
    plugged = [spec.name for spec in default_registry().kind_plugins()]  # Nav2's, among them
    assert "RecoveryNode" in plugged
    assert listed == sorted(KINDS) + plugged
    assert "RecoveryNode  [composite]" in run.stdout
    assert ("    - number_of_retries: input port int = 1  Recoveries allowed before "
            "failing.") in run.stdout
    assert "    - memory: boolean (required)  true: resume" in run.stdout
    assert f"    Unlike BT.CPP: {KINDS['retry'].differences}" in run.stdout
    assert "_skipIf" not in run.stdout and "- children" not in run.stdout


def test_plugins_json(tmp_path: Path) -> None:
    run = sar_tree("plugins", "--json", "--plugin-path", str(GENERIC_PLUGINS), cwd=tmp_path)
    assert run.returncode == 0, run.stderr
    data = {p["name"]: p for p in json.loads(run.stdout)}
    typed = data["Typed"]
    assert typed["source"].endswith("plugins.py")
    assert typed["params"][0] == {"name": "count", "type": "int", "required": False,
                                  "description": "How many.", "default": 1, "minimum": 0,
                                  "maximum": 100}
    assert typed["params"][2]["required"] is True
    assert typed["params"][5]["ref"] == "Fixed"


def test_render_text(tmp_path: Path) -> None:
    write(tmp_path, "good.yaml", GOOD)
    run = sar_tree("render", "good.yaml", "--format", "ascii", "--plugin-path",
                   str(GENERIC_PLUGINS), cwd=tmp_path)
    assert run.returncode == 0, run.stderr
    assert "Retry" in run.stdout and "Fixed" in run.stdout


def test_render_bad_extension_is_usage_error(tmp_path: Path) -> None:
    write(tmp_path, "good.yaml", GOOD)
    run = sar_tree("render", "good.yaml", "-o", "out.xyz", "--plugin-path",
                   str(GENERIC_PLUGINS), cwd=tmp_path)
    assert run.returncode == 2
    no_traceback(run)


def test_render_invalid_tree_exits_1(tmp_path: Path) -> None:
    write(tmp_path, "bad.yaml", BAD)
    run = sar_tree("render", "bad.yaml", "--plugin-path", str(GENERIC_PLUGINS), cwd=tmp_path)
    assert run.returncode == 1
    assert "bad.yaml:4:16: error" in run.stderr


def test_schema_to_file(tmp_path: Path) -> None:
    run = sar_tree("schema", "-o", str(tmp_path / "s.json"))
    assert run.returncode == 0, run.stderr
    schema = json.loads((tmp_path / "s.json").read_text())
    assert schema["$schema"] == "https://json-schema.org/draft/2020-12/schema"
    assert "kind.one_shot" in schema["$defs"]


def test_seed_fixture_validates_with_builtin_plugins() -> None:
    run = sar_tree("validate", str(FIXTURES / "search_and_rescue.yaml"))
    assert run.returncode == 0, run.stderr


def test_render_shows_the_params_a_tree_sets(tmp_path: Path) -> None:
    write(tmp_path, "typed.yaml", "format: 1\nroot: {Typed: {label: hello, rate: 2.5}}\n")
    args = ("render", "typed.yaml", "--format", "ascii", "--plugin-path", str(GENERIC_PLUGINS))
    run = sar_tree(*args, cwd=tmp_path)
    assert run.returncode == 0, run.stderr
    assert run.stdout == '--> Typed rate=2.5, label="hello"\n'
    everything = sar_tree(*args, "--all-params", cwd=tmp_path)
    assert everything.returncode == 0, everything.stderr
    assert everything.stdout == (
        '--> Typed count=1, rate=2.5, loud=false, label="hello"\n')
