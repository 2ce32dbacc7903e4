"""Texels of the atlas and the exact surface point each one samples (thesis §7.1.2-7.1.3).

The thesis averaged triangle centres per texel ("patch"); here every texel
centre maps to an exact surface point by barycentric interpolation in float64,
with the interpolated shading normal.  Three kinds of texels get a point:

``COVERED``  the texel centre lies in a chart triangle;
``NEAR``     bilinear filtering at some point of a chart triangle reads this
             texel (its centre is within one texel, L-infinity, of the
             triangle): slivers thinner than a texel still get texels;
``PADDING``  further rings around each chart, grown outward from the above.

Near and padding texels take the point of their nearest chart triangle
closest to their centre (the chart's rim), so filtering across a chart
border reads the surface's own AO instead of an empty texel, and never a
point extrapolated into the solid at a concave crease.

Memory is linear in texels: two full-size maps while rasterising (8 bytes per
image texel), then compact arrays of the texels in use (13 bytes each); points
and normals are computed on demand for one batch at a time (a bake of up to
:data:`..rays.targets.GEOMETRY_CACHE_TEXELS` texels keeps them, 72 bytes a texel).
"""

from dataclasses import dataclass

import numpy as np

from ..arrays.geometry2d import (band_x_extent, box_holds_texel_centre, closest_barycentric, corner_max, corner_min,
                                 point_keys, triangle_score)
from ..arrays.graph import group_starts, index_in_runs, index_type, sort_order
from ..arrays.grid import neighbour_texels, neighbour_values
from .rim import edge_twins, member_rim, rim_triangles, side_twins

COVERED, NEAR, PADDING = 0, 1, 2
#: Points on a triangle's rim move this far (times the object size) into it: twice
#: the ray origins' lift (:data:`..rays.ray_setup.ORIGIN_OFFSET`), see :func:`_inset_rim_points`.
RIM_INSET = 2.0e-5
#: Rim points move at least this many texels into their triangle (:data:`RIM_INSET` where more): a
#: texel at a chart's rim holds the AO a quarter texel inside, not the exact rim's (:func:`texel_geometry`).
RIM_TEXELS = 0.25

#: Rasterise at most this many candidate texels at once (bounds peak memory).
CHUNK = 1 << 22


@dataclass
class Texels:
    """The texels that carry AO.

    Attributes
    ----------
    width, height : int
    index : (n,) int64
        Flat texel index ``y * width + x``, ascending.
    member : (n,) int64
        Atlas member (triangle in a chart) whose surface the texel samples.
    kind : (n,) int8
        :data:`COVERED`, :data:`NEAR` or :data:`PADDING`.
    ring : (n,) int8
        0 for covered and near texels, ``r`` for the r-th padding ring.
    """

    width: int
    height: int
    index: np.ndarray
    member: np.ndarray
    kind: np.ndarray
    ring: np.ndarray = None

    def __len__(self):
        return len(self.index)

    def next_in_row(self, chart, selection=slice(None)):
        """(k,) int64: for each texel of ``selection`` (a slice or (n,) bool), the position within it of the
        texel right of it when that one is selected too and holds the same ``chart`` ((n,) int), else -1."""
        index, chart = self.index[selection], chart[selection]
        beside = np.flatnonzero((index[1:] == index[:-1] + 1) & (index[1:] % self.width != 0)
                                & (chart[1:] == chart[:-1]))
        result = np.full(len(index), -1, dtype=np.int64)
        result[beside] = beside + 1
        return result

    def xy(self, selection=slice(None)):
        """(k, 2) int64 texel column and row."""
        index = self.index[selection]
        return np.stack([index % self.width, index // self.width], axis=1)


def rasterise(atlas, mesh, padding=4):
    """All texels that carry AO, with the member each one samples.

    Parameters
    ----------
    atlas : Atlas
    mesh : TriangleMesh
    padding : int
        Rings of padding texels grown around the near texels of each chart.

    Returns
    -------
    Texels
    """
    one_texel = atlas.chart_texel >= 0
    drawn = ~one_texel[atlas.member_chart]
    live = np.flatnonzero(atlas.member_placed & ~mesh.degenerate[atlas.member_triangle] & drawn)
    # charts stored as one texel: that texel samples the chart's largest triangle
    fixed = one_texel & (atlas.chart_texel_member >= 0)
    fixed_texel, first = np.unique(atlas.chart_texel[fixed], return_index=True)
    fixed_member = atlas.chart_texel_member[fixed][first]
    return rasterise_triangles(atlas.member_uv, live, atlas.width, atlas.height, padding,
                               fixed_texel=fixed_texel, fixed_member=fixed_member, rim=_live_rim(atlas, mesh, live))


def _live_rim(atlas, mesh, live):
    """(k,) bool: :func:`.rim.rim_triangles` of members ``live`` (k,), a corner being one vertex in one chart
    (:func:`.rim.member_rim`, through the mesh's pairs of sides)."""
    twin = side_twins(mesh.triangles) if mesh.side_edge is None else edge_twins(mesh.side_edge, mesh.triangles)
    return member_rim(twin, mesh.triangles, atlas.member_triangle, atlas.member_chart, atlas.charts.chart_axis,
                      atlas.membership, live)


def rasterise_triangles(triangle_uv, live, width, height, padding=4, fixed_texel=None, fixed_member=None, rim=None):
    """Texels of an image covered by (or within one texel of) some 2D triangles.

    Scanline rasterisation: for every triangle and texel row, the covered
    texels are one interval (centres inside the triangle) and the near texels
    another (centres within one texel of it); only the near texels that no
    triangle covers are scored against each other.  A near texel lies outside
    the triangles' union, so only the triangles on its border (``rim``) need
    their near intervals drawn.

    Parameters
    ----------
    triangle_uv : (m, 3, 2) float64, texel coordinates
    live : (k,) int, which triangles to draw
    width, height : int
    padding : int, rings grown around the near texels
    fixed_texel, fixed_member : (p,) int, optional
        Texels assigned beforehand (covered, sampling ``fixed_member``):
        charts stored as one texel.
    rim : (k,) bool, optional
        The live triangles on the border of the union (:func:`rim_triangles`);
        found from shared corners' coordinates when not given.

    Returns
    -------
    Texels whose ``member`` indexes ``triangle_uv``.
    """
    member_map = np.full(width * height, -1, dtype=index_type(width * height))
    kind = np.full(width * height, PADDING, dtype=np.int8)
    if fixed_texel is not None and len(fixed_texel):
        member_map[fixed_texel] = fixed_member
        kind[fixed_texel] = COVERED
    _draw_triangles(member_map, kind, triangle_uv, np.asarray(live, dtype=np.int64), width, height, rim)
    ring = _grow_padding(member_map, kind, width, height, padding)
    index = np.flatnonzero(member_map >= 0)
    return Texels(width, height, index, member_map[index].astype(np.int64), kind[index], ring[index])


def _draw_triangles(member_map, kind, triangle_uv, live, width, height, rim):
    """Write the covered and near texels of triangles ``live`` into ``member_map`` and ``kind`` (w * h,)
    (:func:`rasterise_triangles`); what it works with (about 200 bytes a drawn triangle) goes on return, before
    the padding grows."""
    if rim is None:
        rim = rim_triangles(point_keys(triangle_uv[live].reshape(-1, 2)).reshape(-1, 3))

    # Covered texels: every centre inside a triangle (a centre exactly on a
    # shared edge goes to one of the two; both are the same surface there).
    # Only a triangle whose box holds a texel centre can cover one: at a
    # million triangles and 256² about one in twenty-five.
    drawn = live[box_holds_texel_centre(triangle_uv, live)]
    uv = triangle_uv[drawn]
    row_member, row_y, x0, x1 = covered_rows(uv, height)
    del uv
    c0 = np.clip(np.ceil(x0 - 0.5), 0, width).astype(np.int64)
    c1 = np.clip(np.floor(x1 - 0.5), -1, width - 1).astype(np.int64)
    del x0, x1
    for texel, owner in expand_spans(row_y, c0, c1, row_member, width):
        member_map[texel] = drawn[owner]
        kind[texel] = COVERED
    del row_member, row_y, c0, c1

    # Near texels: centres within one texel of a rim triangle that no
    # triangle covers; the closest triangle wins.
    rim_triangle = live[np.flatnonzero(rim)]
    rim_uv = triangle_uv[rim_triangle]
    y0 = np.clip(np.ceil(corner_min(rim_uv)[:, 1] - 1.5), 0, height).astype(np.int64)
    y1 = np.clip(np.floor(corner_max(rim_uv)[:, 1] + 0.5), -1, height - 1).astype(np.int64)
    row_member, row_y = _rows(y0, y1)
    centre_y = row_y + 0.5
    near_low, near_high = band_x_extent(rim_uv[row_member], centre_y - 1.0, centre_y + 1.0)
    n0 = np.clip(np.ceil(near_low - 1.5), 0, width).astype(np.int64)
    n1 = np.clip(np.floor(near_high + 0.5), -1, width - 1).astype(np.int64)
    winners = []
    for texel, owner in expand_spans(row_y, n0, n1, row_member, width):
        free = member_map[texel] < 0
        texel, owner = texel[free], owner[free]
        centre = np.stack([texel % width + 0.5, texel // width + 0.5], axis=1)
        score = triangle_score(rim_uv[owner], centre)
        keep = score > -np.inf
        winners.append(_best_per_texel(texel[keep], score[keep], owner[keep]))
    if winners:
        texel, score, owner = (np.concatenate(column) for column in zip(*winners))
        texel, _, owner = _best_per_texel(texel, score, owner)
        member_map[texel] = rim_triangle[owner]
        kind[texel] = NEAR


def covered_rows(uv, height, half_open=False):
    """Every texel row whose centre line crosses a triangle, and the crossing's x-extent.

    ``half_open``: a row exactly on a triangle's top corner belongs to the triangle above it (rows run
    ``[y_low, y_high)``), so triangles that tile a region cover each row of centres once.

    Each edge is followed from its lower end (lower y, then lower x) with one
    slope, so two triangles sharing an edge compute the same crossing to the
    bit and no texel centre on a shared edge falls between them.

    Parameters
    ----------
    uv : (k, 3, 2) float64, texel coordinates
    height : int

    Returns
    -------
    triangle, y : (r,) int64, the triangle and row of each crossing
    x_low, x_high : (r,) float64
    """
    # one array per corner and coordinate: swaps by np.where, not masked writes into (k, 3) columns
    x = [uv[:, corner, 0] for corner in range(3)]
    y = [uv[:, corner, 1] for corner in range(3)]
    for i, j in ((0, 1), (1, 2), (0, 1)):                   # sort the corners by (y, x)
        swap = (y[j] < y[i]) | ((y[j] == y[i]) & (x[j] < x[i]))
        x[i], x[j] = np.where(swap, x[j], x[i]), np.where(swap, x[i], x[j])
        y[i], y[j] = np.where(swap, y[j], y[i]), np.where(swap, y[i], y[j])

    def slope(i, j):
        rise = y[j] - y[i]
        return np.divide(x[j] - x[i], rise, out=np.zeros(len(rise)), where=rise > 0)

    low_slope, first_slope, second_slope = slope(0, 2), slope(0, 1), slope(1, 2)
    first_row = np.clip(np.ceil(y[0] - 0.5), 0, height).astype(np.int64)
    last_row = np.clip((np.ceil(y[2] - 0.5) - 1) if half_open else np.floor(y[2] - 0.5), -1,
                       height - 1).astype(np.int64)
    triangle, row = _rows(first_row, last_row)
    centre = row + 0.5
    x0, y0 = x[0][triangle], y[0][triangle]
    along_long = x0 + (centre - y0) * low_slope[triangle]
    upper = centre >= y[1][triangle]
    along_short = np.where(upper, x[1][triangle] + (centre - y[1][triangle]) * second_slope[triangle],
                           x0 + (centre - y0) * first_slope[triangle])
    return triangle, row, np.minimum(along_long, along_short), np.maximum(along_long, along_short)


def _rows(y0, y1):
    """Every (triangle, row) pair of rows ``y0..y1`` (inclusive) per triangle: ``(triangle, y)`` (r,) int64."""
    rows = np.maximum(y1 - y0 + 1, 0)
    return np.repeat(np.arange(len(y0)), rows), np.repeat(y0, rows) + index_in_runs(rows)


def _best_per_texel(texel, score, owner):
    """For each distinct texel (k,) int >= 0, in texel order, the entry with the highest score (ties, or all NaN:
    the first): one stable sort by texel, then each run's best (no sort by the score, a float, too)."""
    if not len(texel):
        return texel, score, owner
    order = sort_order(texel)
    sorted_texel, sorted_score = texel[order], score[order]
    bounds = group_starts(sorted_texel)
    best = np.repeat(np.fmax.reduceat(sorted_score, bounds[:-1]), np.diff(bounds))
    at = np.flatnonzero((sorted_score == best) | np.isnan(best))
    pick = order[at[np.concatenate([[True], sorted_texel[at[1:]] != sorted_texel[at[:-1]]])]]
    return texel[pick], score[pick], owner[pick]


def expand_spans(row_y, x_start, x_end, owner, width):
    """Flat texel indices of the spans ``x_start..x_end`` (inclusive) of each row, and their owners.

    Yields ``(texel, owner)`` arrays of about :data:`CHUNK` entries at a time
    (a span is never split, so one huge span may exceed it).
    """
    count = np.maximum(x_end - x_start + 1, 0)
    ends = np.cumsum(count)
    start = 0
    while start < len(count):
        stop = max(int(np.searchsorted(ends, ends[start] - count[start] + CHUNK, side="right")), start + 1)
        part = count[start:stop]
        row = start + np.repeat(np.arange(stop - start), part)
        x = x_start[row] + index_in_runs(part)
        yield row_y[row] * width + x, owner[row]
        start = stop


def _grow_padding(member_map, kind_map, width, height, rings):
    """Grow assigned texels outward by ``rings`` rings (8-neighbourhood), in place.

    Returns the ring number of every image texel (int8, 0 for those assigned before).
    """
    ring_map = np.zeros(width * height, dtype=np.int8)
    assigned = member_map >= 0
    frontier = np.flatnonzero(assigned)
    inner = np.ones(len(frontier), dtype=bool)    # assigned with all 8 neighbours assigned
    for other in neighbour_values(assigned, frontier, width, height, False):
        inner &= other
    frontier = frontier[~inner]
    for ring in range(1, rings + 1):
        if not len(frontier):
            break
        targets, sources, ranks = [], [], []
        for rank, (target, inside) in enumerate(neighbour_texels(frontier, width, height)):
            target = target[inside]
            empty = member_map[target] < 0
            targets.append(target[empty])
            sources.append(frontier[inside][empty])
            ranks.append(np.full(int(empty.sum()), rank))
        target, source, rank = np.concatenate(targets), np.concatenate(sources), np.concatenate(ranks)
        order = sort_order(target, rank, source)
        target, source = target[order], source[order]
        first = np.ones(len(target), dtype=bool)
        first[1:] = target[1:] != target[:-1]
        target, source = target[first], source[first]
        member_map[target] = member_map[source]
        kind_map[target] = PADDING
        ring_map[target] = ring
        frontier = target
    return ring_map


def texel_geometry(texels, atlas, mesh, selection=slice(None)):
    """Surface point and normals sampled by some texels.

    A texel samples the point of its member triangle nearest to its centre
    (in the atlas): its exact surface point if the centre is inside, else
    the closest point of the triangle's edge.  So near and padding texels hold
    the AO at the chart's rim, never a point extrapolated off the surface
    (which, at a concave crease, would lie inside the solid).  Points on the
    rim (or within :data:`RIM_INSET` of it) move :data:`RIM_TEXELS` of a
    texel into their triangle, at most half way to its centre: AO can jump
    at the exact rim (two plates 10⁻⁴ apart: rays escape through the slit
    from the rim only), and bilinear filtering spreads a rim texel's value
    over the chart's last half texel.

    Parameters
    ----------
    texels : Texels
    atlas : Atlas
    mesh : TriangleMesh
    selection : slice or index array into ``texels``

    Returns
    -------
    points : (k, 3) float64
    normals : (k, 3) float64
        Unit interpolated shading normal.
    geometric : (k, 3) float64
        Unit normal of the member triangle.
    """
    member = texels.member[selection]
    index = texels.index[selection]
    x = (index % texels.width).astype(np.float64) + 0.5
    y = (index // texels.width).astype(np.float64) + 0.5
    triangle = atlas.member_triangle[member]
    b0, b1, b2 = closest_barycentric(atlas.member_uv[member], x, y)
    corners = mesh.positions[mesh.triangles[triangle]]                     # (k, 3, 3)
    points = b0[:, None] * corners[:, 0] + b1[:, None] * corners[:, 1] + b2[:, None] * corners[:, 2]
    inset = RIM_INSET * mesh.triangle_scale[triangle]
    points = _inset_rim_points(points, _rim_distance(mesh, triangle, (b0, b1, b2)) < inset, corners.mean(axis=1),
                               np.maximum(inset, RIM_TEXELS / max(atlas.density, 1e-300)))
    normals = mesh.normals_of(triangle)
    normals = b0[:, None] * normals[:, 0] + b1[:, None] * normals[:, 1] + b2[:, None] * normals[:, 2]
    geometric = mesh.triangle_normal[triangle]
    length = np.sqrt((normals * normals).sum(axis=1))[:, None]
    ok = length > 1e-12
    normals = np.where(ok, normals / np.where(ok, length, 1.0), geometric)
    return points, normals, geometric


def _rim_distance(mesh, triangle, bary):
    """(k,) float64: distance of the points at barycentrics ``bary`` (three (k,) arrays, each >= 0) of
    ``triangle`` (k,) from its border, in object units."""
    height = mesh.corner_height_of(triangle)
    b0, b1, b2 = bary
    return np.minimum(np.minimum(b0 * height[:, 0], b1 * height[:, 1]), b2 * height[:, 2])


def _inset_rim_points(points, rim, centres, inset):
    """Move the ``rim`` points (k,) bool toward their triangle's centre by ``inset`` (float or (k,), at
    most half way).

    A rim point at a concave crease lies exactly in the plane of the other
    face; rays from it into that face's half-space would start on its plane,
    miss it and see the outside (a bright line along the crease).  Inset,
    the point lies strictly on its own face's side of the crease.  A texel
    whose centre falls on (or within the inset of) a side is such a point
    too: where a chart's border runs through texel centres, as a box's walls
    do at some densities, a whole column of texels sat on the crease.
    """
    towards = centres[rim] - points[rim]
    length = np.sqrt((towards * towards).sum(axis=1))
    inset = np.broadcast_to(np.asarray(inset, dtype=np.float64), rim.shape)[rim]
    step = np.minimum(inset, 0.5 * length) / np.maximum(length, 1e-300)
    points[rim] += towards * step[:, None]
    return points


