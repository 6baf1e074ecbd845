"""The test run's clean-up of Fast DDS shared-memory files nobody uses (no ROS needed)."""

from __future__ import annotations

import mmap
from pathlib import Path

from sar_testing.shm_zombies import remove_unused_fastdds_files


def test_files_no_process_maps_or_holds_go_and_used_ones_stay(tmp_path: Path) -> None:
    for name in ("fastrtps_port7411", "sem.fastrtps_port7411_mutex", "fastrtps_port7413",
                 "fastrtps_port7415_el", "other_program_segment"):
        (tmp_path / name).write_bytes(b"\0" * 4096)
    with (tmp_path / "fastrtps_port7413").open("r+b") as mapped_file, \
            mmap.mmap(mapped_file.fileno(), 4096) as mapped, \
            (tmp_path / "fastrtps_port7415_el").open("rb"):
        removed = remove_unused_fastdds_files(tmp_path)
        assert mapped[0] == 0  # still a live mapping
    assert sorted(removed) == ["fastrtps_port7411", "sem.fastrtps_port7411_mutex"]
    assert sorted(p.name for p in tmp_path.iterdir()) == [
        "fastrtps_port7413", "fastrtps_port7415_el", "other_program_segment"]


def test_a_missing_folder_removes_nothing(tmp_path: Path) -> None:
    assert remove_unused_fastdds_files(tmp_path / "absent") == []
