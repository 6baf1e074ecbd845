"""tools/bootstrap.py: idempotent when warm, clear messages when the machine lacks something.

A failed step must leave the next run able to finish: no half-built venv that later
fails obscurely.
"""

from __future__ import annotations

import importlib.util
import json
import os
import subprocess
import sys
from pathlib import Path
from types import ModuleType

import pytest

ROOT = Path(__file__).resolve().parent.parent.parent
BOOTSTRAP = ROOT / "tools" / "bootstrap.py"


def load_bootstrap() -> ModuleType:
    spec = importlib.util.spec_from_file_location("bootstrap_under_test", BOOTSTRAP)
    assert spec and spec.loader
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def run_bootstrap(*args: str, env: dict[str, str]) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, str(BOOTSTRAP), *args], env=env, text=True, capture_output=True,
        timeout=300, check=False,
    )


def test_warm_run_does_nothing_and_says_ready() -> None:
    # make test ran the bootstrap just before pytest, so every step is stamped.
    done = run_bootstrap(env=dict(os.environ))
    assert done.returncode == 0, done.stderr
    assert "environment ready" in done.stdout
    for busy in ("installing", "building", "creating"):
        assert busy not in done.stdout


def test_missing_system_tools_are_named_and_no_venv_is_made(tmp_path: Path) -> None:
    bare = tmp_path / "bin"
    bare.mkdir()
    (bare / "python3.11").symlink_to(sys.executable)  # only an interpreter on PATH
    venv = tmp_path / "venv"
    env = dict(os.environ, PATH=str(bare), SAR_NO_APT="1", SAR_VENV=str(venv))
    done = run_bootstrap("--no-compat", env=env)
    assert done.returncode == 1
    assert "missing system tools: cmake, gcc, g++, make, graphviz" in done.stderr
    assert "apt-get install" in done.stderr
    assert "Traceback" not in done.stderr
    assert not venv.exists()


def test_python_too_old_is_refused(monkeypatch: pytest.MonkeyPatch) -> None:
    bootstrap = load_bootstrap()
    monkeypatch.setattr(bootstrap.sys, "version_info", (3, 9, 18, "final", 0))
    with pytest.raises(bootstrap.SetupError, match="too old"):
        bootstrap.find_python()


def test_python_other_than_311_without_311_explains(monkeypatch: pytest.MonkeyPatch) -> None:
    bootstrap = load_bootstrap()
    monkeypatch.setattr(bootstrap.sys, "version_info", (3, 12, 1, "final", 0))
    monkeypatch.setattr(bootstrap.shutil, "which", lambda _name: None)
    with pytest.raises(bootstrap.SetupError, match=r"built for CPython 3\.11 only"):
        bootstrap.find_python()


def test_unreachable_index_is_explained_and_the_next_run_can_finish(tmp_path: Path) -> None:
    venv = tmp_path / "venv"
    offline = dict(
        os.environ, SAR_VENV=str(venv), PIP_INDEX_URL="http://127.0.0.1:9/simple",
        PIP_EXTRA_INDEX_URL="", PIP_FIND_LINKS="", PIP_RETRIES="0", PIP_TIMEOUT="2",
        PIP_CONSTRAINT="",
    )
    done = run_bootstrap("--no-compat", env=offline)
    assert done.returncode == 1
    assert "could not download packages from the Python package index" in done.stderr
    assert "Traceback (most recent call last)" not in done.stderr.split("pip install")[0]
    # The venv itself is whole; the failed step is not stamped, so the next run redoes it.
    assert (venv / "bin" / "python").exists()
    stamps_file = venv / ".sar-stamps.json"
    stamps = json.loads(stamps_file.read_text()) if stamps_file.exists() else {}
    assert "requirements" not in stamps


def test_broken_venv_is_replaced(tmp_path: Path) -> None:
    bootstrap = load_bootstrap()
    venv = tmp_path / "venv"
    (venv / "bin").mkdir(parents=True)
    (venv / "bin" / "python").write_text("#!/bin/sh\nexit 1\n")  # a half-made venv
    (venv / "bin" / "python").chmod(0o755)
    req = tmp_path / "empty.txt"
    req.write_text("# nothing\n")
    stamps = bootstrap.ensure_venv(sys.executable, venv, [req])
    assert stamps.done("requirements", bootstrap.digest([req]))
    assert subprocess.run([str(venv / "bin" / "python"), "-c", "pass"],
                          check=False).returncode == 0
