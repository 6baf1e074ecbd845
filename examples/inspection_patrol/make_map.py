"""Write the patrol's map, as ``nav2_map_server map_saver_cli`` would: warehouse.pgm + .yaml.

A warehouse of 8 m x 6 m (origin at its south-west corner, -1, -1) with two shelf rows
in the middle. Run it once: ``python make_map.py``.
"""

from pathlib import Path

import numpy as np
from PIL import Image

RESOLUTION = 0.05
ORIGIN = (-1.0, -1.0)
SIZE_M = (8.0, 6.0)


def cell(x: float, y: float, height: int) -> tuple[int, int]:
    """The (row, column) of map point (x, y); row 0 is the north edge."""
    return height - 1 - round((y - ORIGIN[1]) / RESOLUTION), round((x - ORIGIN[0]) / RESOLUTION)


def main(folder: Path = Path(__file__).parent) -> None:
    """Draw the walls and the shelves, then write the image and its yaml."""
    width, height = (round(s / RESOLUTION) for s in SIZE_M)
    pixels = np.full((height, width), 254, dtype=np.uint8)  # trinary: 254 free, 0 occupied
    pixels[:2, :] = pixels[-2:, :] = pixels[:, :2] = pixels[:, -2:] = 0  # outer walls
    for x0, x1 in ((1.0, 2.0), (4.0, 5.0)):  # two shelf rows, from y = 1 to y = 3
        top, left = cell(x0, 3.0, height)
        bottom, right = cell(x1, 1.0, height)
        pixels[top:bottom + 1, left:right + 1] = 0
    Image.fromarray(pixels).save(folder / "warehouse.pgm")
    (folder / "warehouse.yaml").write_text(
        f"image: warehouse.pgm\nmode: trinary\nresolution: {RESOLUTION}\n"
        f"origin: [{ORIGIN[0]}, {ORIGIN[1]}, 0.0]\nnegate: 0\n"
        "occupied_thresh: 0.65\nfree_thresh: 0.25\n", encoding="utf-8")


if __name__ == "__main__":
    main()
