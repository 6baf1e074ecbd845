"""The generated JSON Schema: well-formed, committed up to date, and in agreement with
the fast validator on every document (fixture corpus and generated)."""

from __future__ import annotations

import json
import subprocess
from pathlib import Path
from typing import Any

import jsonschema
import pytest
import yaml
from hypothesis import HealthCheck, event, given, settings

from sar_framework.engine.checking.schema import schema_text, tree_schema
from sar_framework.engine.checking.validate import validate_file
from sar_framework.engine.registry import Registry, discover

from ..checking.test_validate import CASES
from ..conftest import FIXTURES, REPO, VENV_BIN, make_registry
from ..strategies import documents

COMMITTED = REPO / "sar_framework" / "schema" / "tree.schema.json"
"""The core's schema: the engine's kinds and the built-in neutral leaves."""
SAR_COMMITTED = REPO / "plugins" / "sar" / "schema" / "tree.schema.json"
"""The search-and-rescue app's schema: the core's and the app's leaves."""
SAR_LEAVES = "sar_plugins.sar.leaves"
YAML_LEVEL = (
    "YAML", "unsupported YAML tag", "duplicate key", "a mapping key must be", "empty file"
)


def test_schema_is_valid_draft_2020_12(registry: Registry) -> None:
    jsonschema.Draft202012Validator.check_schema(tree_schema(registry))


def test_committed_schema_is_up_to_date() -> None:
    expected = schema_text(discover(entry_points=False))
    assert COMMITTED.read_text(encoding="utf-8") == expected, (
        "sar_framework/schema/tree.schema.json is stale: run "
        "`sar-tree schema --core -o sar_framework/schema/tree.schema.json`"
    )


def test_the_core_schema_names_no_app_leaf() -> None:
    core = json.loads(COMMITTED.read_text(encoding="utf-8"))
    sar = json.loads(SAR_COMMITTED.read_text(encoding="utf-8"))
    app_only = set(sar["$defs"]) - set(core["$defs"])
    assert {"plugin.NavigateToZone", "plugin.DetectSurvivor"} <= app_only
    assert set(core["$defs"]) <= set(sar["$defs"])


def test_committed_app_schema_is_up_to_date() -> None:
    expected = schema_text(discover([SAR_LEAVES], entry_points=False))
    assert SAR_COMMITTED.read_text(encoding="utf-8") == expected, (
        "plugins/sar/schema/tree.schema.json is stale: run `sar-tree schema --core "
        f"--plugin-path {SAR_LEAVES} -o plugins/sar/schema/tree.schema.json`"
    )


@pytest.mark.parametrize(("arguments", "committed"), [
    (["--core"], COMMITTED), (["--core", "--plugin-path", SAR_LEAVES], SAR_COMMITTED)],
    ids=["core", "search_and_rescue"])
def test_cli_schema_matches_committed(arguments: list[str], committed: Path) -> None:
    run = subprocess.run([str(VENV_BIN / "sar-tree"), "schema", *arguments],
                         capture_output=True, text=True, check=False, cwd=REPO)
    assert run.returncode == 0, run.stderr
    assert run.stdout == committed.read_text(encoding="utf-8")


def _verdicts(path: Path, registry: Registry, validator: Any) -> tuple[bool, bool] | None:
    """(fast structural verdict, jsonschema verdict), or None for YAML-level problems."""
    result = validate_file(path, registry=registry)
    if any(d.message.startswith(YAML_LEVEL) for d in result.structural):
        return None
    document = yaml.safe_load(path.read_text(encoding="utf-8"))
    return not result.structural, validator.is_valid(document)


@pytest.fixture(scope="module")
def validator(registry: Registry) -> Any:
    return jsonschema.Draft202012Validator(tree_schema(registry))


def test_agreement_on_fixture_corpus(
    registry: Registry, validator: Any, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(tmp_path)
    paths = sorted(FIXTURES.rglob("*.yaml"))
    for name, (text, _) in CASES.items():
        path = tmp_path / f"{name}.yaml"
        path.write_text(text, encoding="utf-8")
        paths.append(path)
    compared = 0
    for path in paths:
        verdicts = _verdicts(path, registry, validator)
        if verdicts is not None:
            assert verdicts[0] == verdicts[1], path.name
            compared += 1
    assert compared >= 30


_REGISTRY = make_registry()
_VALIDATOR = jsonschema.Draft202012Validator(tree_schema(_REGISTRY))


@settings(max_examples=500, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(document=documents(_REGISTRY))
def test_agreement_on_generated_documents(document: Any, tmp_path_factory: Any) -> None:
    text = yaml.safe_dump(document, sort_keys=False)
    path = tmp_path_factory.mktemp("gen") / "tree.yaml"
    path.write_text(text, encoding="utf-8")
    result = validate_file(path, registry=_REGISTRY)
    fast = not result.structural
    reference = _VALIDATOR.is_valid(yaml.safe_load(text))
    event("valid" if reference else "invalid")
    assert fast == reference, (text, [str(d) for d in result.structural])


def test_the_schema_of_the_same_plugins_is_built_once_and_another_set_gets_its_own(
        registry: Registry) -> None:
    """validate() builds the tree schema once per set of plugins (it was half of its time)."""
    from sar_framework.engine.checking.structure import StructureCheck

    first, again = StructureCheck(registry), StructureCheck(registry.copy())
    assert again.validator is first.validator  # same plugins: the same schema and validator
    fewer = Registry()
    for plugin in list(registry)[1:]:
        fewer.add(plugin.cls, plugin.source)
    other = StructureCheck(fewer)
    assert other.validator is not first.validator
    assert f"plugin.{next(iter(registry)).name}" not in other.schema["$defs"]
