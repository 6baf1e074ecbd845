"""The survivor table: which zone hides a survivor, and where.

A plain YAML file (not a ROS parameter file)::

    survivors:
      zone_a: {x: -2.5, y: 3.2}
      zone_c: {x: 4.1, y: -2.5}

Zones not listed have no survivor. Without a file the spec's table applies.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import yaml

#: The mission spec's ground truth, used when no file is given.
DEFAULT_SURVIVORS: dict[str, tuple[float, float]] = {
    "zone_a": (-2.5, 3.2),
    "zone_c": (4.1, -2.5),
}

#: The repository's table, present in a source checkout or an editable install.
REPO_SURVIVORS_FILE = Path(__file__).resolve().parents[3] / "config" / "survivors.yaml"


class SurvivorsFileError(ValueError):
    """A survivor table that cannot be used; the message names the file and key."""


def _coordinate(value: Any, file: str, key: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise SurvivorsFileError(f"{file}: {key}: must be a number, got {value!r}")
    if not math.isfinite(value):
        raise SurvivorsFileError(f"{file}: {key}: must be finite, got {value!r}")
    return float(value)


def load_survivors(path: str | Path) -> dict[str, tuple[float, float]]:
    """Read a survivor table.

    Args:
        path: The YAML file.

    Returns:
        Zone id -> survivor ``(x, y)`` in frame ``map``.

    Raises:
        SurvivorsFileError: The file is missing, not YAML, or malformed.
    """
    file = str(path)
    try:
        document = yaml.safe_load(Path(path).read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise SurvivorsFileError(f"{file}: file not found") from None
    except (OSError, UnicodeDecodeError) as err:
        raise SurvivorsFileError(f"{file}: cannot read the file: {err}") from None
    except yaml.YAMLError as err:
        raise SurvivorsFileError(f"{file}: YAML error: {' '.join(str(err).split())}") from None
    if not isinstance(document, dict) or not isinstance(document.get("survivors"), dict):
        raise SurvivorsFileError(f"{file}: survivors: expected a mapping 'survivors:' of "
                                 "zone id -> {x, y}")
    table: dict[str, tuple[float, float]] = {}
    for zone_id, entry in document["survivors"].items():
        key = f"survivors.{zone_id}"
        if not isinstance(zone_id, str) or not zone_id:
            raise SurvivorsFileError(f"{file}: {key}: zone ids must be non-empty strings")
        if not isinstance(entry, dict) or "x" not in entry or "y" not in entry:
            raise SurvivorsFileError(f"{file}: {key}: expected a mapping with x and y")
        table[zone_id] = (_coordinate(entry["x"], file, f"{key}.x"),
                          _coordinate(entry["y"], file, f"{key}.y"))
    return table


def default_survivors_source() -> tuple[dict[str, tuple[float, float]], str]:
    """Return the default table and where it came from.

    Returns:
        The repository's ``config/survivors.yaml`` when it exists, else the spec's table;
        paired with a label for the log.

    Raises:
        SurvivorsFileError: The repository file exists but is malformed.
    """
    if REPO_SURVIVORS_FILE.is_file():
        return load_survivors(REPO_SURVIVORS_FILE), str(REPO_SURVIVORS_FILE)
    return dict(DEFAULT_SURVIVORS), "built-in table"
