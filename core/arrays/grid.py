"""Passes over each texel's 8 neighbours in the atlas image (flat indices ``y * width + x``).

The adaptive stop asks whether a texel's neighbours agree, weighted rays take
the largest blend weight around a texel, the buried-texel pass looks for a
seen neighbour, and padding grows ring by ring: all through
:func:`neighbour_texels`, in the one order :data:`NEIGHBOURS`.
"""

import numpy as np

#: The 8-neighbourhood as (dx, dy), sides before corners.
NEIGHBOURS = ((1, 0), (-1, 0), (0, 1), (0, -1), (1, 1), (-1, 1), (1, -1), (-1, -1))


def neighbour_texels(index, width, height):
    """Each of the 8 neighbours of some texels, in the order of :data:`NEIGHBOURS`.

    Parameters
    ----------
    index : (k,) int, flat texel indices of a ``width`` x ``height`` image

    Yields
    ------
    neighbour : (k,) int64, flat index of the neighbour (clamped into the image where it lies outside)
    inside : (k,) bool, the neighbour lies in the image
    """
    index = np.asarray(index, dtype=np.int64)
    x, y = index % width, index // width
    for dx, dy in NEIGHBOURS:
        nx, ny = x + dx, y + dy
        inside = (nx >= 0) & (nx < width) & (ny >= 0) & (ny < height)
        yield np.clip(ny, 0, height - 1) * width + np.clip(nx, 0, width - 1), inside


def neighbour_values(image, index, width, height, outside):
    """Each neighbour's value in a flat ``image`` (width * height,), ``outside`` beyond the image's edge.

    Yields (k,) arrays, one per neighbour, in the order of :data:`NEIGHBOURS`.
    """
    for neighbour, inside in neighbour_texels(index, width, height):
        yield np.where(inside, image[neighbour], outside)
