"""The stand-in nav2_msgs / tf2_msgs are Jazzy's definitions, field for field and constant for
constant, with no text of their own.

The reference is the real package: its installed definition where the real package is built
into the environment, else the upstream sources in ``../shared/ros-overlay/src``.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

import pytest

REPO_ROOT = Path(__file__).resolve().parents[2]
STAND_INS = REPO_ROOT / "interfaces" / "stand_ins"
# Upstream Jazzy sources next to the checkout (../shared, or ../../shared from a worktree).
OVERLAY_SRC = next((p / "shared" / "ros-overlay" / "src" for p in REPO_ROOT.parents
                    if (p / "shared" / "ros-overlay" / "src").is_dir()), Path("/nonexistent"))
DEFINITIONS = sorted(
    str(p.relative_to(STAND_INS))
    for p in STAND_INS.rglob("*")
    if p.suffix in (".msg", ".srv", ".action")
)


def installed_real(relative: str) -> Path | None:
    """The real package's installed definition, or None when only the stand-in is installed."""
    package = relative.split("/", 1)[0]
    for prefix in [*os.environ.get("AMENT_PREFIX_PATH", "").split(os.pathsep), sys.prefix]:
        share = Path(prefix) / "share"
        manifest = share / package / "package.xml"
        if (share / relative).is_file() and manifest.is_file() \
                and "Stand-in" not in manifest.read_text():
            return share / relative
    return None


def reference(relative: str) -> Path:
    """Jazzy's definition of ``relative`` (``pkg/action/Name.action``); skip when unavailable."""
    found = installed_real(relative)
    if found is None and (OVERLAY_SRC / relative).is_file():
        found = OVERLAY_SRC / relative
    if found is None:
        pytest.skip(f"no real {relative} here (neither installed nor in ../shared/ros-overlay)")
    return found


def parse(path: Path):
    """Parse a definition with rosidl_adapter (the parser behind ``ros2 interface show``)."""
    from rosidl_adapter import parser

    package, kind, file_name = path.parts[-3:]
    name, text = Path(file_name).stem, path.read_text()
    if kind == "action":
        spec = parser.parse_action_string(package, name, text)
        return [spec.goal, spec.result, spec.feedback]
    if kind == "srv":
        spec = parser.parse_service_string(package, name, text)
        return [spec.request, spec.response]
    return [parser.parse_message_string(package, name, text)]


def test_there_are_stand_ins() -> None:
    assert "nav2_msgs/action/NavigateToPose.action" in DEFINITIONS
    assert "tf2_msgs/msg/TFMessage.msg" in DEFINITIONS


@pytest.mark.parametrize("relative", DEFINITIONS)
def test_fields_and_constants_are_jazzys(relative: str) -> None:
    real, ours = parse(reference(relative)), parse(STAND_INS / relative)
    for real_part, our_part in zip(real, ours, strict=True):
        assert [str(f) for f in our_part.fields] == [str(f) for f in real_part.fields]
        assert [(c.type, c.name, c.value) for c in our_part.constants] == [
            (c.type, c.name, c.value) for c in real_part.constants
        ]


@pytest.mark.parametrize("relative", DEFINITIONS)
def test_no_text_of_our_own(relative: str) -> None:
    """``ros2 interface show`` prints comments: a stand-in must not add any."""
    real_lines = {line.strip() for line in reference(relative).read_text().splitlines()}
    comments = [line.strip() for line in (STAND_INS / relative).read_text().splitlines()
                if "#" in line]
    assert [c for c in comments if c not in real_lines] == []


@pytest.mark.parametrize("relative", DEFINITIONS)
def test_ros2_interface_show_of_the_real_package_matches(relative: str) -> None:
    """Where the real package and the ros2 CLI are installed: what users see, line for line."""
    import subprocess

    from sar_testing.ros2_cli import ros2_executable

    executable = ros2_executable()
    if executable is None or installed_real(relative) is None:
        pytest.skip("needs the real package and the ros2 command line installed")
    name = relative.rsplit(".", 1)[0]  # nav2_msgs/action/NavigateToPose
    env = {**os.environ, "AMENT_PREFIX_PATH": os.environ.get("AMENT_PREFIX_PATH", sys.prefix)}
    shown = subprocess.run([sys.executable, executable, "interface", "show", name,
                            "--no-comments"], capture_output=True, text=True, env=env,
                           timeout=60, check=True).stdout
    top_level = [line for line in shown.splitlines() if line and not line[0].isspace()]
    ours = [line for line in (STAND_INS / relative).read_text().splitlines() if line.strip()]
    assert top_level == ours
