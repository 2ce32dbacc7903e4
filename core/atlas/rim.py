"""Which triangles of a region have a side on its border: the only ones whose near texels the rasteriser draws
(:mod:`.raster`).

A side is inside the region when exactly one other triangle has the same
side the other way round (the two lie on either side of it); any other side
(used once, three times, or twice in the same direction, a fold) is on the
border.  :func:`rim_triangles` applies that rule to corners given as keys
(:func:`side_twins` of the keys);
:func:`member_rim` to the members of an atlas, a corner being one vertex in
one chart, through the mesh's own pairs of sides, worked out once for all
charts: a side's only partner in any chart is its twin in the mesh, so each
member side is judged by looking its twin's triangle up in the same chart,
with no sort of every member's sides (over a million members and their
overlaps, that sort was the largest step of a cheap bake's rasterising).
The twins come from the mesh's edge numbers where the reader gave them
(:func:`edge_twins`, no sort at all), else from its vertices (:func:`side_twins`).
"""

import numpy as np

from ..arrays.blocks import row_blocks
from ..arrays.graph import sort_order
from ..arrays.reduce import row_all

#: :func:`side_twins` of a side with no twin: no other side joins its two vertices, or one other does the same
#: way round (or it joins a vertex to itself).  Inside no region.
ALONE = -1
#: :func:`side_twins` of a side that two or more other sides share (a non-manifold edge): judged by the rule.
SHARED = -2


def rim_triangles(corner_key):
    """Triangles with a side on the border of the region they cover together.

    The rule is the module's.  Every point of the region's border lies on a
    border side, so a texel centre within one texel of the region but outside
    it is within one texel of a rim triangle.

    Parameters
    ----------
    corner_key : (k, 3) int, >= 0
        Corners with equal keys are the same 2D point (e.g. one vertex in one chart).

    Returns
    -------
    (k,) bool
    """
    return ~row_all(side_twins(corner_key) >= 0)


def side_twins(triangles):
    """The twin of every side of a mesh: the one other side on the same two vertices, the other way round.

    Parameters
    ----------
    triangles : (t, 3) int >= 0, vertex indices (or any keys: corners with equal keys are one point)

    Returns
    -------
    (t, 3) int64
        For side ``j`` of triangle ``i`` (from corner ``j`` to the next): ``3 i' + j'``, its twin, where exactly
        one other side joins its two vertices and runs the other way; :data:`ALONE` where no other does, one
        other does the same way round, or the side joins a vertex to itself; :data:`SHARED` where two or more
        others do.
    """
    triangles = np.asarray(triangles, dtype=np.int64).reshape(-1, 3)
    if triangles.size and int(triangles.max()) >= 2**31:           # a side's key is two vertices' in one int64
        triangles = np.unique(triangles, return_inverse=True)[1].reshape(-1, 3)
    start = triangles.ravel()
    end = np.roll(triangles, -1, axis=1).ravel()
    # one key a side, whichever way it runs
    side_key = np.minimum(start, end)
    side_key *= int(triangles.max(initial=0)) + 1
    side_key += np.maximum(start, end)
    forward = start < end
    order = sort_order(side_key, stable=False)         # a run of one side is judged whatever its order
    side_key, forward = side_key[order], forward[order]
    count = len(order)
    same_as_next = side_key[1:] == side_key[:-1]
    # runs of exactly two: equal to the next, and neither of them equal to its other neighbour
    two = same_as_next.copy()
    two[1:] &= ~same_as_next[:-1]
    two[:-1] &= ~same_as_next[1:]
    in_run = np.zeros(count, dtype=bool)              # shares its key with another side
    in_run[:-1] = same_as_next
    in_run[1:] |= same_as_next
    twin = np.full(count, ALONE, dtype=np.int64)
    twin[in_run] = SHARED
    first = np.flatnonzero(two)
    twin[first] = twin[first + 1] = ALONE                # a pair the same way round: a fold, on the border
    first = first[forward[first] != forward[first + 1]]
    twin[first], twin[first + 1] = order[first + 1], order[first]
    twin[(start == end)[order]] = ALONE
    result = np.empty(count, dtype=np.int64)
    result[order] = twin
    return result.reshape(-1, 3)


def edge_twins(side_edge, triangles):
    """:func:`side_twins` from each side's edge number, with no sort: the same result where two sides share a
    number exactly when they join the same two vertices (:attr:`..mesh.triangle_mesh.TriangleMesh.side_edge`).
    Numbers that pair two sides on different vertices are no edges: :func:`side_twins` then.

    Blender keeps one edge per pair of vertices, so its edges number the faces' sides so; a quad's inner
    diagonal joins two vertices that some other side may join too (a non-manifold mesh's), and then its two
    sides pair here where the vertices alone would call them shared.  Either way a side called inside has a
    triangle on each side of it (the rasteriser's need), so only which near texels are drawn may differ.

    Parameters
    ----------
    side_edge : (t, 3) int >= 0, the edge of side ``j`` (from corner ``j`` to the next) of each triangle
    triangles : (t, 3) int, vertex indices

    Returns
    -------
    (t, 3) int64, as :func:`side_twins`
    """
    edge = np.asarray(side_edge, dtype=np.int64).ravel()
    triangles = np.asarray(triangles, dtype=np.int64).reshape(-1, 3)
    start = triangles.ravel()                                             # the vertex each side starts at
    if not len(edge):
        return np.zeros((0, 3), dtype=np.int64)
    side = np.arange(len(edge), dtype=np.float64)                # (indices below 2**53: exact as floats)
    sides = np.bincount(edge)[edge]
    # an edge of two sides: each side's twin is their sum less itself
    twin = np.bincount(edge, weights=side)[edge]
    twin -= side
    twin = twin.astype(np.int64)
    twin[sides != 2] = ALONE
    twin[sides > 2] = SHARED
    twin_start = start[np.maximum(twin, 0)]
    alone = twin < 0
    # two sides on one edge start at one vertex when they run the same way round (a fold, on the border), and
    # the other way round each starts where the other ends; numbers that pair sides otherwise do not follow
    # the vertices (a mesh whose corners' edges are wrong): its vertices decide instead
    fold = twin_start == start
    fold &= ~alone
    end = np.empty_like(triangles)
    end[:, :2] = triangles[:, 1:]
    end[:, 2] = triangles[:, 0]
    follows = twin_start == end.ravel()
    follows |= fold
    follows |= alone
    if not follows.all():
        return side_twins(triangles)
    twin[fold] = ALONE
    return twin.reshape(-1, 3)


def member_rim(twin, triangles, member_triangle, member_chart, chart_axis, membership, live):
    """:func:`rim_triangles` of an atlas' members ``live``, a corner being one vertex in one chart: the same
    result, from the mesh's :func:`side_twins`.

    A member side's only possible partner is its twin's, the member of the twin's triangle in the same chart
    (a triangle has at most one member a chart: one chart an axis), if it is live too; sides of a non-manifold
    edge (:data:`SHARED`) go to the rule itself, all of them at once.

    Parameters
    ----------
    twin : (t, 3) int, :func:`side_twins` of ``triangles`` (t, 3) int
    member_triangle, member_chart : (m,) int, each member's triangle and chart
    chart_axis : (c,) int, 0..5, each chart's signed axis
    membership : (t, 3) int, each triangle's member on axis X, Y, Z (-1: none)
    live : (k,) int, the members whose region it is

    Returns
    -------
    (k,) bool
    """
    live = np.asarray(live, dtype=np.int64)
    # the chart of each live member, -1 for the others and for one more at the end (what a side with no
    # twin looks up): a side is inside when its twin's member in its chart is live
    live_chart = np.full(len(member_triangle) + 1, -1, dtype=np.int64)
    live_chart[live] = member_chart[live]
    chart_plane = np.asarray(chart_axis) // 2
    flat_membership = np.asarray(membership).ravel()
    inside = np.empty((len(live), 3), dtype=bool)
    shared = []
    for rows in row_blocks(len(live)):           # a block at a time: every temporary a few MB
        member = live[rows]
        chart = member_chart[member]
        side_twin = twin[member_triangle[member]]                        # (b, 3)
        partner = flat_membership[side_twin // 3 * 3 + chart_plane[chart][:, None]]
        partner[side_twin < 0] = -1
        inside[rows] = live_chart[partner] == chart[:, None]
        shared.append(np.flatnonzero(side_twin == SHARED) + 3 * rows.start)
    shared = np.concatenate(shared) if shared else np.zeros(0, dtype=np.int64)
    if len(shared):
        row, side = shared // 3, shared % 3
        member = live[row]
        corner = triangles[member_triangle[member]]
        ends = np.stack([corner[np.arange(len(row)), side], corner[np.arange(len(row)), (side + 1) % 3]], axis=1)
        key = member_chart[member][:, None] * np.int64(int(triangles.max(initial=0)) + 1) + ends
        # each as a triangle of its two ends and a point of its own: only its first side can pair
        own = np.arange(len(row), dtype=np.int64)[:, None] + int(key.max(initial=0)) + 1
        inside.ravel()[shared] = side_twins(np.concatenate([key, own], axis=1))[:, 0] >= 0
    return ~row_all(inside)
