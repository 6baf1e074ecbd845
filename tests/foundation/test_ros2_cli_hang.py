"""A ``ros2`` command line that hangs is killed and asked again, not a failed test."""

from __future__ import annotations

from pathlib import Path

from sar_testing.launch_ctrl_c import node_names


def hangs_once(tmp_path: Path) -> list[str]:
    """A stand-in for ``ros2 node list``: its first run hangs, later runs list two nodes."""
    marker = tmp_path / "ran-once"
    script = (f"if [ -e {marker} ]; then echo /a; echo /b; "
              f"else touch {marker}; exec sleep 600; fi")
    return ["sh", "-c", script]


def test_a_node_listing_that_hangs_is_asked_again(tmp_path: Path) -> None:
    listed = node_names({"/a", "/b"}, bound_s=120.0, command=hangs_once(tmp_path), hang_s=1.0)
    assert sorted(listed) == ["/a", "/b"]
    assert (tmp_path / "ran-once").exists()  # the hung first run did happen


def test_a_listing_that_never_names_the_nodes_ends_at_the_bound(tmp_path: Path) -> None:
    listed = node_names({"/a", "/c"}, bound_s=0.0, command=hangs_once(tmp_path), hang_s=1.0)
    assert listed == []  # only the hung run fitted in the bound: nothing was listed
