"""2D geometry on arrays of triangles and segments (chart projections, atlas UVs, texel coordinates).

Every function takes stacked shapes, ``(k, 3, 2)`` triangles or ``(k, 2)``
points, and answers for all ``k`` at once; float64 throughout.
"""

import numpy as np

from .blocks import row_blocks
from .graph import scatter_rows


def cross2d(a, b):
    """z component of the cross product of 2D vectors: ``a``, ``b`` (..., 2) -> (...,)."""
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def corner_min(shape):
    """Smallest of each shape's corners: ``shape`` (k, c, ...) -> (k, ...) (c = 2 or 3).

    The same as ``shape.min(axis=1)``, several times faster for so few corners.
    """
    return _corner_reduce(np.minimum, shape)


def corner_max(shape):
    """Largest of each shape's corners: ``shape`` (k, c, ...) -> (k, ...) (c = 2 or 3)."""
    return _corner_reduce(np.maximum, shape)


def _corner_reduce(ufunc, shape):
    """``ufunc`` (np.minimum or np.maximum) over the corners of each shape, one coordinate at a time: numpy's
    element-wise loop over (k, 2) views runs two items per row (30 ms a million triangles' UVs), over a
    coordinate's (k,) view all k at once (9 ms)."""
    shape = np.asarray(shape)
    count, corners = shape.shape[:2]
    flat = shape.reshape(count, corners, int(np.prod(shape.shape[2:], dtype=np.int64)))
    out = np.empty((count, flat.shape[2]), dtype=shape.dtype)
    for coordinate in range(flat.shape[2]):
        column = out[:, coordinate]
        ufunc(flat[:, 0, coordinate], flat[:, 1, coordinate], out=column)
        for corner in range(2, corners):
            ufunc(column, flat[:, corner, coordinate], out=column)
    return out.reshape((count,) + shape.shape[2:])


def group_boxes(triangle, group, count):
    """Bounding box of each group of 2D triangles: ``low, high`` (count, 2) float64.

    ``triangle`` (k, 3, 2), ``group`` (k,) int in ``[0, count)``; an empty group
    gets ``low = inf, high = -inf``.
    """
    return boxes_of_groups(corner_min(triangle), corner_max(triangle), group, count)


def boxes_of_groups(low, high, group, count):
    """Bounding box of each group of boxes ``low, high`` (k, 2), ``group`` (k,) int in ``[0, count)``:
    ``low, high`` (count, 2) float64, ``inf, -inf`` for an empty group."""
    group_low = scatter_rows(np.minimum, np.full((count, 2), np.inf), group, low)
    group_high = scatter_rows(np.maximum, np.full((count, 2), -np.inf), group, high)
    return group_low, group_high


def band_x_extent(triangle, band_low, band_high):
    """x-extent of each 2D triangle (r, 3, 2) clipped to a horizontal band [band_low, band_high] (r,).

    The clipped polygon's corners are the triangle's corners inside the band and
    the crossings of its edges with the band's two lines, so the extent over
    those points is exact.  Returns ``(low, high)``, ``(inf, -inf)`` where the
    band misses the triangle.  Both bounds must be finite.
    """
    low = np.full(len(triangle), np.inf)
    high = np.full(len(triangle), -np.inf)
    x, y = triangle[..., 0], triangle[..., 1]
    for k in range(3):                                   # corners inside the band
        inside = (y[:, k] >= band_low) & (y[:, k] <= band_high)
        low = np.where(inside, np.minimum(low, x[:, k]), low)
        high = np.where(inside, np.maximum(high, x[:, k]), high)
    for k in range(3):                                   # edges crossing the band's borders
        px, py, qx, qy = x[:, k], y[:, k], x[:, (k + 1) % 3], y[:, (k + 1) % 3]
        dy = qy - py
        for line in (band_low, band_high):
            crosses = (np.minimum(py, qy) <= line) & (line <= np.maximum(py, qy)) & (dy != 0)
            at = px + (line - py) * (qx - px) / np.where(dy != 0, dy, 1.0)
            low = np.where(crosses, np.minimum(low, at), low)
            high = np.where(crosses, np.maximum(high, at), high)
    return low, high


def separated(uv_a, uv_b, margin):
    """Separating-axis test for 2D triangles, with a margin.

    Parameters
    ----------
    uv_a, uv_b : (k, 3, 2) float64
    margin : float or (k,) float
        The triangles count as touching unless some axis separates them by
        more than ``margin``; a negative margin demands that much penetration.

    Returns
    -------
    (k,) bool: True where an axis (x, y or an edge normal) separates them.
    """
    margin = np.broadcast_to(np.asarray(margin, dtype=np.float64), (len(uv_a),))
    normals = []
    for tri in (uv_a, uv_b):
        edge = np.roll(tri, -1, axis=1) - tri
        normal = np.stack([-edge[..., 1], edge[..., 0]], axis=-1)
        length = np.linalg.norm(normal, axis=-1, keepdims=True)
        normals.append(np.divide(normal, length, out=np.zeros_like(normal), where=length > 0))
    unit = np.broadcast_to(np.eye(2), (len(uv_a), 2, 2))
    axes = np.concatenate([unit] + normals, axis=1)                       # (k, 8, 2)
    ax, ay = axes[..., 0], axes[..., 1]

    def interval(tri):
        p0, p1, p2 = (tri[:, c, 0, None] * ax + tri[:, c, 1, None] * ay for c in range(3))
        return np.minimum(np.minimum(p0, p1), p2), np.maximum(np.maximum(p0, p1), p2)

    low_a, high_a = interval(uv_a)
    low_b, high_b = interval(uv_b)
    gap = np.maximum(low_b - high_a, low_a - high_b)
    live = (ax != 0) | (ay != 0)
    return (live & (gap > margin[:, None])).any(axis=1)


def barycentric_2d(points, tri):
    """2D barycentric coordinates (k, 3) of ``points`` (k, 2) in ``tri`` (k, 3, 2)."""
    a, b, c = tri[:, 0], tri[:, 1], tri[:, 2]
    v0, v1, v2 = b - a, c - a, points - a
    den = cross2d(v0, v1)
    den = np.where(np.abs(den) > 0, den, np.inf)
    w1 = cross2d(v2, v1) / den
    w2 = cross2d(v0, v2) / den
    return np.stack([1.0 - w1 - w2, w1, w2], axis=1)


def line_crossing(r, d1, d2):
    """Where the lines ``p0 + t d1`` and ``q0 + u d2`` meet, with ``r = q0 - p0`` (all (k, 2)).

    Returns ``t``, ``u`` (k,) and whether the lines meet at one point (not parallel).
    """
    den = cross2d(d1, d2)
    meet = np.abs(den) > 0
    safe = np.where(meet, den, np.inf)
    return cross2d(r, d2) / safe, cross2d(r, d1) / safe, meet


def segment_distance(p0, p1, q0, q1):
    """Closest points of 2D segments ``p0-p1`` and ``q0-q1``.

    Parameters
    ----------
    p0, p1, q0, q1 : (k, 2) float64

    Returns
    -------
    distance : (k,) float64
    s, t : (k,) float64
        Parameters of the closest points on each segment, in [0, 1].
    """
    d1, d2, r = p1 - p0, q1 - q0, q0 - p0
    # per component: numpy's sums over a trailing axis of 2 are slow, and x + y is the same sum
    options = []
    for point, start, direction, on_first in ((q0, p0, d1, True), (q1, p0, d1, True),
                                              (p0, q0, d2, False), (p1, q0, d2, False)):
        dx, dy = direction[:, 0], direction[:, 1]
        length2 = dx * dx + dy * dy
        along = (point[:, 0] - start[:, 0]) * dx + (point[:, 1] - start[:, 1]) * dy
        param = np.clip(np.divide(along, length2, out=np.zeros(len(length2)), where=length2 > 0), 0.0, 1.0)
        gap_x = start[:, 0] + param * dx - point[:, 0]
        gap_y = start[:, 1] + param * dy - point[:, 1]
        options.append((np.sqrt(gap_x * gap_x + gap_y * gap_y), param, on_first))
    distance = np.full(len(p0), np.inf)
    s = np.zeros(len(p0))
    t = np.zeros(len(p0))
    for k, (gap, param, on_first) in enumerate(options):
        better = gap < distance
        distance = np.where(better, gap, distance)
        fixed = float(k % 2)                     # the endpoint used: 0 for p0/q0, 1 for p1/q1
        s = np.where(better, param if on_first else fixed, s)
        t = np.where(better, fixed if on_first else param, t)
    cs, ct, meet = line_crossing(r, d1, d2)
    cross = meet & (cs >= 0) & (cs <= 1) & (ct >= 0) & (ct <= 1)
    # the lines' crossing, measured rather than assumed: for (nearly) collinear
    # segments the parameters are 0 / tiny and the "crossing" may be far apart
    apart_x = p0[:, 0] + cs * d1[:, 0] - (q0[:, 0] + ct * d2[:, 0])
    apart_y = p0[:, 1] + cs * d1[:, 1] - (q0[:, 1] + ct * d2[:, 1])
    apart = np.sqrt(apart_x * apart_x + apart_y * apart_y)
    cross &= apart < distance
    distance = np.where(cross, apart, distance)
    s = np.where(cross, cs, s)
    t = np.where(cross, ct, t)
    return distance, s, t


def triangle_angles(corners):
    """Interior angle at each corner of 2D triangles: ``corners`` (k, 3, 2) -> (k, 3).

    Computed on x and y columns, corner by corner: the same arithmetic as on
    (k, 3, 2) blocks, in 60% of the time (no gathered copies of the block).
    """
    x = [np.ascontiguousarray(corners[:, i, 0]) for i in range(3)]
    y = [np.ascontiguousarray(corners[:, i, 1]) for i in range(3)]
    angles = np.empty(corners.shape[:2])
    for i in range(3):
        j, k = (i + 1) % 3, (i + 2) % 3
        e1x, e1y, e2x, e2y = x[j] - x[i], y[j] - y[i], x[k] - x[i], y[k] - y[i]
        angles[:, i] = np.abs(np.arctan2(e1x * e2y - e1y * e2x, e1x * e2x + e1y * e2y))
    return angles


def box_holds_texel_centre(triangles, chosen):
    """(k,) bool: whether the bounding box of each triangle ``chosen`` (k,) int of ``triangles`` (m, 3, 2) float64
    (texel coordinates) holds a texel centre, give or take :data:`BOX_SLACK` texels (crossings computed along a
    side may round an ulp past its corners).  A block of triangles at a time (:func:`.blocks.row_blocks`): no
    copy of every chosen triangle's corners (48 bytes each)."""
    holds = np.empty(len(chosen), dtype=bool)
    for block in row_blocks(len(chosen)):
        corners = triangles[chosen[block]]
        low, high = corner_min(corners), corner_max(corners)                  # (b, 2)
        inside = np.floor(high - (0.5 - BOX_SLACK)) >= np.ceil(low - (0.5 + BOX_SLACK))
        holds[block] = inside[:, 0] & inside[:, 1]
    return holds


#: Texels a triangle's box is widened by before :func:`box_holds_texel_centre` asks whether it holds a centre.
BOX_SLACK = 1e-6


def triangle_score(triangle, point):
    """How well a texel centre belongs to a triangle, in texels.

    Parameters
    ----------
    triangle : (k, 3, 2) float64, texel coordinates
    point : (k, 2) float64

    Returns
    -------
    (k,) float64: signed distance from the triangle's boundary (positive
    inside); ``-inf`` where a one-texel square around the point misses the
    triangle (bilinear filtering inside the triangle never reads this texel).
    """
    # on x and y columns: the same arithmetic as on (k, 2) rows, three times faster
    x = [np.ascontiguousarray(triangle[:, i, 0]) for i in range(3)]
    y = [np.ascontiguousarray(triangle[:, i, 1]) for i in range(3)]
    px, py = point[:, 0], point[:, 1]
    negative = (x[1] - x[0]) * (y[2] - y[0]) - (y[1] - y[0]) * (x[2] - x[0]) < 0
    inside = np.full(len(triangle), np.inf)
    reach = np.ones(len(triangle), dtype=bool)
    for p, q in ((1, 2), (2, 0), (0, 1)):              # edge opposite a, b, c
        ex, ey = x[q] - x[p], y[q] - y[p]
        length = np.sqrt(ex * ex + ey * ey)
        signed = (ex * (py - y[p]) - ey * (px - x[p])) / np.where(length > 0, length, np.inf)
        signed = np.where(negative, -signed, signed)
        support = np.divide(np.abs(ex) + np.abs(ey), length, out=np.full(len(length), np.inf), where=length > 0)
        inside = np.minimum(inside, signed)
        reach &= signed >= -support - 1e-9
    for column, coordinate in ((x, px), (y, py)):
        reach &= coordinate >= np.minimum(np.minimum(column[0], column[1]), column[2]) - 1.0 - 1e-9
        reach &= coordinate <= np.maximum(np.maximum(column[0], column[1]), column[2]) + 1.0 + 1e-9
    return np.where(reach, inside, -np.inf)


def point_keys(points):
    """Dense integer key of each 2D point (k, 2) float64: equal keys for equal coordinates."""
    if not len(points):
        return np.zeros(0, dtype=np.int64)
    points = points + 0.0                         # -0.0 and 0.0 are one point
    order = np.lexsort((points[:, 1], points[:, 0]))
    ordered = points[order]
    new = np.ones(len(order), dtype=bool)
    new[1:] = (ordered[1:] != ordered[:-1]).any(axis=1)
    keys = np.empty(len(order), dtype=np.int64)
    keys[order] = np.cumsum(new) - 1
    return keys


def closest_barycentric(triangle, x, y):
    """Barycentric coordinates of the point of each 2D triangle closest to (x, y).

    Parameters
    ----------
    triangle : (k, 3, 2) float64
    x, y : (k,) float64

    Returns
    -------
    b0, b1, b2 : (k,) float64, each in [0, 1], summing to 1 (Ericson's region
    tests; inside points keep their own coordinates).
    """
    a, b, c = triangle[:, 0], triangle[:, 1], triangle[:, 2]
    p = np.stack([x, y], axis=1)
    ab, ac, ap = b - a, c - a, p - a
    d1, d2 = (ab * ap).sum(1), (ac * ap).sum(1)
    bp = p - b
    d3, d4 = (ab * bp).sum(1), (ac * bp).sum(1)
    cp = p - c
    d5, d6 = (ab * cp).sum(1), (ac * cp).sum(1)
    va = d3 * d6 - d5 * d4
    vb = d5 * d2 - d1 * d6
    vc = d1 * d4 - d3 * d2
    k = len(x)
    out = np.zeros((k, 3))
    done = np.zeros(k, dtype=bool)

    def take(mask, weights):
        nonlocal done
        mask = mask & ~done
        out[mask] = np.stack([w[mask] if np.ndim(w) else np.full(mask.sum(), w) for w in weights], axis=1)
        done |= mask

    safe = lambda num, den: np.divide(num, den, out=np.zeros(k), where=den != 0)  # noqa: E731
    take((d1 <= 0) & (d2 <= 0), (1.0, 0.0, 0.0))                                   # corner a
    take((d3 >= 0) & (d4 <= d3), (0.0, 1.0, 0.0))                                  # corner b
    v = safe(d1, d1 - d3)
    take((vc <= 0) & (d1 >= 0) & (d3 <= 0), (1.0 - v, v, 0.0))                     # edge ab
    take((d6 >= 0) & (d5 <= d6), (0.0, 0.0, 1.0))                                  # corner c
    w = safe(d2, d2 - d6)
    take((vb <= 0) & (d2 >= 0) & (d6 <= 0), (1.0 - w, 0.0, w))                     # edge ac
    w = safe(d4 - d3, (d4 - d3) + (d5 - d6))
    take((va <= 0) & ((d4 - d3) >= 0) & ((d5 - d6) >= 0), (0.0, 1.0 - w, w))       # edge bc
    total = va + vb + vc
    v, w = safe(vb, total), safe(vc, total)
    inside_weights = (1.0 - v - w, v, w)
    take(np.ones(k, dtype=bool), inside_weights)                                   # inside
    degenerate = np.abs(cross2d(ab, ac)) <= 0
    out[degenerate] = 1.0 / 3.0
    return out[:, 0], out[:, 1], out[:, 2]
