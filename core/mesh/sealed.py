"""Which triangles belong to (nearly) closed pieces: the only faces whose back means "inside".

A ray whose first hit is the back of a face started behind that face.  For
a face of a closed piece with its normals outward, that means the ray
started inside the piece, so a point most of whose rays do so is buried
(:func:`..rays.ao.buried_by_vote`).  Behind an open sheet (a drape before a wall, a card)
the same back-face hits mean nothing of the kind: the point is seen round
the sheet's edges.  So only back-face hits on sealed triangles count.

Real pieces are seldom watertight (Suzanne's head is open behind her eyes,
her eyes are open at the back), so "closed" is measured, not required: the
area-weighted normals of a closed surface sum to zero, those of a flat sheet
to its area, those of a shell with a hole to the hole's area.
"""

import numpy as np

from ..arrays.reduce import column_max, column_min
from .weld import vertex_pieces

#: A piece is sealed when its area-weighted normals sum to less than this fraction of its area (a closed
#: surface 0, a hemisphere one half, a flat sheet 1; tests/bench/bench_buried.py prints the openings of real
#: pieces: Suzanne's eyes, open at the back, and a wavy drape).
MAX_OPENING = 0.75


def sealed_triangles(positions, triangles, max_opening=MAX_OPENING, vertex_piece=None):
    """Triangles of pieces that are closed, or nearly, with their normals outward.

    A piece is a set of triangles joined by vertices at the same position.
    Its opening is ``|sum of a_i n_i| / sum of a_i`` over its triangles
    (area a, unit normal n): 0 for a closed surface, the projected area of
    the holes over the whole area otherwise.  It is sealed when the opening is
    below ``max_opening`` and its signed volume about its own area centroid is
    positive (normals outward: an inside-out piece would make every point
    outside it look buried).  Both depend on the piece alone, so moving or
    rotating it, or adding other pieces, changes nothing; ``triangles`` must be
    wound counter-clockwise seen from the outside in the space of
    ``positions`` (see :func:`..rays.ray_setup.world_winding` for mirrored objects).

    Parameters
    ----------
    positions : (v, 3) float
    triangles : (t, 3) int
    max_opening : float in [0, 1]
    vertex_piece : (v,) int, optional: :func:`.weld.vertex_pieces` of these triangles, if already worked out
        (for the positions of a mesh moved or turned as a whole: pieces do not change with it)

    Returns
    -------
    (t,) bool
    """
    triangles = np.asarray(triangles, dtype=np.int64).reshape(-1, 3)
    if not len(triangles):
        return np.zeros(0, dtype=bool)
    positions = np.asarray(positions, dtype=np.float64).reshape(-1, 3)
    if vertex_piece is None:
        vertex_piece = vertex_pieces(positions, triangles)
    piece = np.asarray(vertex_piece)[triangles[:, 0]]
    pieces = int(piece.max()) + 1
    centre = 0.5 * (column_min(positions) + column_max(positions))            # only for precision
    # (3, t) each, gathered a coordinate at a time from contiguous columns: the rows' (t, 3).T is strided, and
    # every product below read it so (the same values either way)
    columns = [np.ascontiguousarray(positions[:, k]) - centre[k] for k in range(3)]
    a, b, c = (np.stack([column[corner] for column in columns]) for corner in np.ascontiguousarray(triangles.T))
    u, v = b - a, c - a
    cross = (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])   # 2 * area * normal
    twice_area = np.sqrt(cross[0] ** 2 + cross[1] ** 2 + cross[2] ** 2)
    area = np.bincount(piece, weights=twice_area, minlength=pieces)
    normal_sum = np.stack([np.bincount(piece, weights=k, minlength=pieces) for k in cross], axis=1)
    opening = np.sqrt((normal_sum * normal_sum).sum(axis=1)) / np.maximum(area, 1e-300)
    # Outward: 6 x the signed volume of the fan from the piece's own area centroid, sum of (a - p) . (b - a) x (c - a).
    # A closed piece's is the same about any point; an open piece's depends on the point, and the piece's own
    # centroid moves with it and is blind to the rest of the scene.
    centroid = np.stack([np.bincount(piece, weights=twice_area * (a[k] + b[k] + c[k]) / 3.0, minlength=pieces)
                         for k in range(3)], axis=1) / np.maximum(area, 1e-300)[:, None]
    volume = np.bincount(piece, weights=a[0] * cross[0] + a[1] * cross[1] + a[2] * cross[2], minlength=pieces)
    volume -= (centroid * normal_sum).sum(axis=1)
    return ((opening < max_opening) & (volume > 0.0) & (area > 0.0))[piece]
