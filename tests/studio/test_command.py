"""``sar-tree studio`` on the command line: its modes, and bad input said in one line."""

from __future__ import annotations

from pathlib import Path

import pytest

from sar_framework.cli import main


def test_help_lists_live_replay_and_edit(capsys) -> None:
    assert main(["studio", "--help"]) == 0
    out = capsys.readouterr().out
    for mode in ("live", "replay", "edit"):
        assert f"    {mode}" in out
    assert main(["studio", "live", "--help"]) == 0
    assert "127.0.0.1" in capsys.readouterr().out


def test_edit_refuses_a_file_outside_the_roots(capsys, tmp_path: Path) -> None:
    assert main(["studio", "edit", str(tmp_path / "tree.yaml")]) == 2
    err = capsys.readouterr().err
    assert "outside the directories open to the studio" in err
    assert "add its directory with --root" in err


def test_a_missing_recording_is_named(capsys) -> None:
    assert main(["studio", "replay", "nowhere.mcap"]) == 2
    assert "recording not found: 'nowhere.mcap'" in capsys.readouterr().err


def test_a_missing_or_broken_tree_file_is_said_without_a_traceback(capsys,
                                                                  tmp_path: Path) -> None:
    assert main(["studio", "live", "--tree", "nowhere.yaml"]) == 2
    assert "tree file not found: 'nowhere.yaml'" in capsys.readouterr().err
    bad = tmp_path / "bad.yaml"
    bad.write_text("format: 1\nname: bad\nroot:\n  sequence: {name: S, children: [{Nope: {}}]}\n")
    assert main(["studio", "live", "--tree", str(bad)]) == 1
    err = capsys.readouterr().err
    assert f"{bad}:4:" in err and "Traceback" not in err


@pytest.mark.ros
def test_a_file_that_is_no_recording_is_said_in_one_line(capsys, tmp_path: Path) -> None:
    fake = tmp_path / "fake.mcap"
    fake.write_text("not an mcap file")
    assert main(["studio", "replay", str(fake)]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"sar-tree studio: error: {fake}: cannot read the recording")
    assert "Traceback" not in err


def test_a_port_in_use_is_said_before_anything_starts(capsys) -> None:
    import socket

    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen()
        port = taken.getsockname()[1]
        assert main(["studio", "replay", "nowhere.mcap", "--port", str(port)]) == 2
    err = capsys.readouterr().err
    assert f"cannot listen on 127.0.0.1:{port}: Address already in use" in err
    assert "recording not found" not in err
