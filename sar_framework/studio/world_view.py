"""The world as the studio draws it: walls, the app's places in order and its base.

The walls are the occupancy grid's occupied cells, sent as runs per row (``[row, first
column, length]``) so the page draws a few thousand rectangles instead of a bitmap: no
image library in the page, and a grid the size of ours (260 x 220 cells) is a few kB.
Live, the grid is the one the map server latches on ``/map``; replayed, the ``/map`` the
recording kept (:func:`occupancy_view`); before ``/map`` arrives or in a recording without
one, the simulator's default map file (:data:`~sar_framework.report_map.MAP_YAML`). The
places and the base come from the mission parameter file, read by the apps
(:attr:`~sar_framework.app.App.layout`).

No ROS here: the ROS feed hands :func:`grid_view` plain numbers.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

from sar_framework.app.discovery import installed_apps
from sar_framework.report_map import MAP_YAML

if TYPE_CHECKING:
    from sar_framework.app import App
    from sar_framework.sim.occupancy import OccupancyGrid

#: A cell at or above this occupancy (0-100, as ``nav_msgs/OccupancyGrid``) is a wall.
OCCUPIED_AT = 65


def grid_view(width: int, height: int, resolution: float, origin: tuple[float, float],
              cells: Sequence[int]) -> dict[str, Any]:
    """The page's walls from a grid given row by row from the minimum y.

    Args:
        width: Cells along x.
        height: Cells along y.
        resolution: Metres per cell.
        origin: ``(x, y)`` of the lower-left corner of cell (0, 0), metres.
        cells: ``width * height`` occupancies (-1 unknown, 0 free .. 100 occupied).

    Returns:
        ``{"width", "height", "resolution", "origin": [x, y], "walls": [[row, col, n]...]}``.
    """
    runs: list[list[int]] = []
    for row in range(height):
        line = cells[row * width:(row + 1) * width]
        col = 0
        while col < width:
            if line[col] >= OCCUPIED_AT:
                start = col
                while col < width and line[col] >= OCCUPIED_AT:
                    col += 1
                runs.append([row, start, col - start])
            else:
                col += 1
    return {"width": width, "height": height, "resolution": resolution,
            "origin": [origin[0], origin[1]], "walls": runs}


def file_grid_view(map_yaml: Path = MAP_YAML) -> dict[str, Any]:
    """The page's walls from a map_server yaml file (the course map by default)."""
    from sar_framework.sim.occupancy import load_map

    return occupancy_view(load_map(map_yaml))


def occupancy_view(grid: OccupancyGrid) -> dict[str, Any]:
    """The page's walls from an occupancy grid (a map file's, a recording's ``/map``)."""
    from sar_framework.sim.occupancy import OCCUPIED

    cells = [100 if value == OCCUPIED else 0 for value in grid.data.ravel().tolist()]
    return grid_view(grid.width, grid.height, grid.resolution,
                     (grid.origin_x, grid.origin_y), cells)


def world_view(params_file: str | Path | None, grid: dict[str, Any] | None = None,
               apps: Sequence[App] | None = None) -> dict[str, Any]:
    """The page's map: the grid (the course map when None), the places and the base.

    Args:
        params_file: The mission parameter file, if known (the first app that finds
            places or a base in it gives them).
        grid: :func:`grid_view`'s document, e.g. from ``/map``.
        apps: The apps asked (the installed ones when None).
    """
    apps = installed_apps() if apps is None else apps
    layouts = ([app.layout(str(params_file)) for app in apps if app.layout]
               if params_file else [])
    layout = next((found for found in layouts if found.get("places") or found.get("base")), {})
    return {"grid": grid if grid is not None else file_grid_view(),
            "places": layout.get("places", []), "base": layout.get("base") or None}
