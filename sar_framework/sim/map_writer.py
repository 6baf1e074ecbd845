"""Write nav2 map_server files (PGM + YAML) from an occupancy grid.

The command regenerates the committed map from the world file::

    python -m sar_framework.sim.map_writer [--world maps/final_project_world.yaml]
                                           [--out maps/final_project_map]
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from sar_framework.sim.occupancy import (
    DEFAULT_MAP_PREFIX,
    DEFAULT_RESOLUTION,
    FREE,
    FREE_THRESH,
    OCCUPIED,
    OCCUPIED_THRESH,
    PGM_FREE,
    PGM_OCCUPIED,
    PGM_UNKNOWN,
    OccupancyGrid,
    rasterize,
)
from sar_framework.sim.world import DEFAULT_WORLD_PATH, WorldError, load_world


def _format_number(value: float) -> str:
    """Shortest decimal text of ``value`` after rounding away float noise (``-6.4``, ``0.05``)."""
    text = repr(round(float(value), 9))
    return "0.0" if text == "-0.0" else text


def write_map(grid: OccupancyGrid, prefix: str | Path) -> tuple[Path, Path]:
    """Write ``<prefix>.pgm`` and ``<prefix>.yaml`` as nav2 map_saver does (trinary mode).

    Output bytes depend only on the grid, so regenerating an unchanged world is a no-op.

    Args:
        grid: The grid to save.
        prefix: Output path without extension.

    Returns:
        ``(pgm_path, yaml_path)``.
    """
    prefix = Path(prefix)
    prefix.parent.mkdir(parents=True, exist_ok=True)
    pgm_path = prefix.with_name(prefix.name + ".pgm")
    yaml_path = prefix.with_name(prefix.name + ".yaml")
    pixels = np.full(grid.data.shape, PGM_UNKNOWN, dtype=np.uint8)
    pixels[grid.data == FREE] = PGM_FREE
    pixels[grid.data == OCCUPIED] = PGM_OCCUPIED
    header = (
        f"P5\n# CREATOR: sar_framework.sim.occupancy {grid.resolution:.3f} m/pix\n"
        f"{grid.width} {grid.height}\n255\n"
    )
    pgm_path.write_bytes(header.encode("ascii") + np.flipud(pixels).tobytes())
    yaml_path.write_text(
        f"image: {pgm_path.name}\n"
        "mode: trinary\n"
        f"resolution: {_format_number(grid.resolution)}\n"
        f"origin: [{_format_number(grid.origin_x)}, {_format_number(grid.origin_y)}, 0.0]\n"
        "negate: 0\n"
        f"occupied_thresh: {OCCUPIED_THRESH}\n"
        f"free_thresh: {FREE_THRESH}\n",
        encoding="utf-8",
    )
    return pgm_path, yaml_path


def main(argv: Sequence[str] | None = None) -> int:
    """Command line: rasterise a world file and write the map_server pair.

    Args:
        argv: Arguments (default: ``sys.argv[1:]``).

    Returns:
        Exit status: 0 on success, 1 when the world file is bad.
    """
    parser = argparse.ArgumentParser(
        prog="python -m sar_framework.sim.map_writer",
        description="Rasterise a world file into a nav2 map_server map (PGM + YAML).",
    )
    parser.add_argument("--world", type=Path, default=DEFAULT_WORLD_PATH, help="world YAML")
    parser.add_argument(
        "--out", type=Path, default=DEFAULT_MAP_PREFIX, help="output path without extension"
    )
    parser.add_argument("--resolution", type=float, default=DEFAULT_RESOLUTION, help="m/cell")
    args = parser.parse_args(argv)
    try:
        world = load_world(args.world)
    except WorldError as exc:
        sys.stderr.write(f"error: {exc}\n")
        return 1
    grid = rasterize(world, resolution=args.resolution)
    pgm, yaml_file = write_map(grid, args.out)
    sys.stdout.write(f"wrote {pgm} and {yaml_file} ({grid.width}x{grid.height} cells)\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
