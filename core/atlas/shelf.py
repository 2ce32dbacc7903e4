"""Shelf packing of small rectangles into boxes (the tiny charts of a layout).

Many tiny charts cost a general packer (xatlas) a run time that grows with
their number, and each would get its own padding.  Here they are laid in
rows ("shelves"), tallest first, inside square boxes; each box then goes to
xatlas as one rectangle.  Sizes are whole texels, so each rectangle's place
is a whole texel too.
"""

from dataclasses import dataclass

import numpy as np


@dataclass
class Shelves:
    """Where every rectangle went.

    Attributes
    ----------
    box : (n,) int64
        Box of each rectangle.
    x, y : (n,) int64
        Lower-left corner of each rectangle inside its box (texels).
    box_size : (b, 2) int64
        Used width and height of each box.
    """

    box: np.ndarray
    x: np.ndarray
    y: np.ndarray
    box_size: np.ndarray


def shelf_pack(width, height, box_side):
    """Rectangles ``width`` x ``height`` (n,) int (each at most ``box_side``) into boxes of ``box_side``.

    Rectangles are sorted tallest first and filled left to right into rows;
    a row starts a new box when it would overflow the box's height.  Only the
    rows loop in Python (a row takes its rectangles with one ``searchsorted``).

    Returns
    -------
    Shelves
    """
    width = np.asarray(width, dtype=np.int64)
    height = np.asarray(height, dtype=np.int64)
    count = len(width)
    box = np.zeros(count, dtype=np.int64)
    x = np.zeros(count, dtype=np.int64)
    y = np.zeros(count, dtype=np.int64)
    if not count:
        return Shelves(box, x, y, np.zeros((0, 2), dtype=np.int64))
    order = np.lexsort((-width, -height))
    end_of = np.concatenate([[0], np.cumsum(width[order])])
    sizes = []
    start, current, cursor, used_width = 0, 0, 0, 0
    while start < count:
        stop = max(start + 1, int(np.searchsorted(end_of, end_of[start] + box_side, side="right")) - 1)
        row = order[start:stop]
        row_height = int(height[order[start]])
        if cursor + row_height > box_side:
            sizes.append((used_width, cursor))
            current, cursor, used_width = current + 1, 0, 0
        box[row] = current
        x[row] = end_of[start:stop] - end_of[start]
        y[row] = cursor
        used_width = max(used_width, int(end_of[stop] - end_of[start]))
        cursor += row_height
        start = stop
    sizes.append((used_width, cursor))
    return Shelves(box, x, y, np.array(sizes, dtype=np.int64))
