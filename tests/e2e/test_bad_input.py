"""``sar-tree run`` rejects bad input with exit code 2, a clear message and no traceback."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from .helpers import DEFAULT_TREE, REPO

pytestmark = pytest.mark.ros  # no ROS process starts, but the run module is exercised


def _run(*args: str, cwd: Path = REPO) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "sar_framework", "run", *args],
                          capture_output=True, text=True, timeout=60, cwd=cwd, check=False)


def _assert_rejected(result: subprocess.CompletedProcess[str]) -> str:
    text = result.stdout + result.stderr
    assert result.returncode == 2, text
    assert "Traceback" not in text
    assert "sar-tree run:" not in result.stdout  # nothing was started
    return result.stderr


def test_missing_tree_file(tmp_path: Path) -> None:
    err = _assert_rejected(_run(str(tmp_path / "nope.yaml"), "--report-dir", str(tmp_path)))
    assert f"tree not found: '{tmp_path / 'nope.yaml'}'" in err


def test_tree_with_a_validation_error_is_reported_gcc_style(tmp_path: Path) -> None:
    tree = tmp_path / "bad.yaml"
    tree.write_text("format: 1\nname: bad\nroot:\n  sequence:\n    name: S\n"
                    "    children:\n      - NavigateToZonee: {}\n")
    err = _assert_rejected(_run(str(tree), "--report-dir", str(tmp_path / "r")))
    assert f"{tree}:7:9: error:" in err
    assert "NavigateToZone" in err  # did-you-mean
    assert not (tmp_path / "r").exists()


def test_malformed_params_file(tmp_path: Path) -> None:
    params = tmp_path / "params.yaml"
    params.write_text("/**:\n  ros__parameters:\n    zone_order: [zone_a\n")
    err = _assert_rejected(_run(str(DEFAULT_TREE), "--params", str(params),
                                "--report-dir", str(tmp_path / "r")))
    assert str(params) in err and "error" in err


def test_missing_params_file(tmp_path: Path) -> None:
    err = _assert_rejected(_run(str(DEFAULT_TREE), "--params", str(tmp_path / "none.yaml")))
    assert "parameter file not found" in err


def test_bad_option_values(tmp_path: Path) -> None:
    assert "--speed must be > 0 and <= 1000, got 0.0" in _assert_rejected(
        _run(str(DEFAULT_TREE), "--speed", "0"))
    assert "expected NAME:=VALUE" in _assert_rejected(
        _run(str(DEFAULT_TREE), "--sim-param", "speed=3"))
    _assert_rejected(_run(str(DEFAULT_TREE), "--speed", "fast"))  # argparse


@pytest.mark.parametrize(("value", "problem"), [
    ("-5", "--sim-timeout must be a positive number of seconds, got -5"),
    ("0", "--sim-timeout must be a positive number of seconds, got 0"),
    ("nan", "--sim-timeout must be a positive number of seconds, got nan"),
    ("soon", "argument --sim-timeout: invalid float value: 'soon'"),
])
def test_bad_sim_timeout(value: str, problem: str, tmp_path: Path) -> None:
    err = _assert_rejected(_run(str(DEFAULT_TREE), f"--sim-timeout={value}",
                                "--report-dir", str(tmp_path / "r")))
    assert problem in err
    assert not (tmp_path / "r").exists()


SET_TREE = ("format: 1\nname: drain\nblackboard:\n  battery: {type: float, initial: 60.0}\n"
            "root:\n  Script: {code: \"battery := battery - 1\"}\n")


def test_a_set_value_of_the_wrong_type_is_located_at_the_declaration(tmp_path: Path) -> None:
    tree = tmp_path / "drain.yaml"
    tree.write_text(SET_TREE)
    err = _assert_rejected(_run(str(tree), "--set", "battery=full",
                                "--report-dir", str(tmp_path / "r")))
    assert (f"{tree}:4:3: error: --set battery=full: expected a float, got 'full' "
            "(the entry is declared here as float)") in err, err
    assert not (tmp_path / "r").exists()


def test_a_set_of_an_unknown_entry_gets_a_did_you_mean(tmp_path: Path) -> None:
    tree = tmp_path / "drain.yaml"
    tree.write_text(SET_TREE)
    err = _assert_rejected(_run(str(tree), "--set", "batery=5"))
    assert "the tree declares no entry 'batery' (did you mean 'battery'?)" in err, err


def test_a_set_without_a_value_is_refused(tmp_path: Path) -> None:
    tree = tmp_path / "drain.yaml"
    tree.write_text(SET_TREE)
    err = _assert_rejected(_run(str(tree), "--set", "battery"))
    assert "--set 'battery': expected NAME=VALUE (e.g. battery=50)" in err, err
