"""Which triangles of one chart overlap in the chart's projection.

A chart is injective when no two of its triangles cover the same 2D point
(shared edges and vertices excepted).  Candidates come from a uniform grid
(:mod:`.candidates`), so the cost is O(n log n) for any mesh whose triangles
are not wildly different in size, never O(n²).
"""

import numpy as np

from ..arrays.geometry2d import (barycentric_2d, corner_max, corner_min, line_crossing, segment_distance, separated,
                                 triangle_angles)
from ..arrays.graph import group_starts, index_in_runs, pairs_within_groups, sort_order, unique_pairs, unique_rows
from .candidates import candidate_pairs, may_conflict, without_flat_groups, without_quiet_sides
from .sides import chart_sides
from .steep import steep_pairs


def overlap_depth_gap(uv_a, depth_a, uv_b, depth_b, closed=False):
    """Largest depth difference between two planar triangles over their 2D overlap.

    The overlap of two triangles is a convex polygon whose corners are corners
    of one triangle inside the other, or crossings of their edges; the depth
    difference is linear over it, so its maximum sits at one of those points.

    Parameters
    ----------
    uv_a, uv_b : (k, 3, 2) float64
    depth_a, depth_b : (k, 3) float64
        Depth (distance along the chart's axis) at each corner.
    closed : bool
        Also count corners on the other triangle's edges and crossings at
        edge ends: the overlap's closure, for pairs whose interiors are known
        to overlap (two triangles on one side of a side they share).  A
        triangle lying inside another with a corner on its edge (collinear
        sides, as at a scan's pole) has no other corners.

    Returns
    -------
    (k,) float64: max |depth_a - depth_b| over the overlap, ``-1`` where the
    interiors do not overlap (``closed``: where the triangles do not meet).
    """
    k = len(uv_a)
    gap = np.full(k, -1.0)
    eps = -1e-9 if closed else 1e-9
    for uv_p, depth_p, uv_q, depth_q in ((uv_a, depth_a, uv_b, depth_b), (uv_b, depth_b, uv_a, depth_a)):
        for corner in range(3):
            bary = barycentric_2d(uv_p[:, corner], uv_q)
            inside = (bary > eps).all(axis=1)
            diff = np.abs(depth_p[:, corner] - (bary * depth_q).sum(axis=1))
            gap = np.where(inside, np.maximum(gap, diff), gap)
    for i in range(3):
        p0, p1 = uv_a[:, i], uv_a[:, (i + 1) % 3]
        dp0, dp1 = depth_a[:, i], depth_a[:, (i + 1) % 3]
        d1 = p1 - p0
        for j in range(3):
            q0, q1 = uv_b[:, j], uv_b[:, (j + 1) % 3]
            dq0, dq1 = depth_b[:, j], depth_b[:, (j + 1) % 3]
            t, u, meet = line_crossing(q0 - p0, d1, q1 - q0)
            cross = meet & (t > eps) & (t < 1 - eps) & (u > eps) & (u < 1 - eps)
            diff = np.abs(dp0 + t * (dp1 - dp0) - (dq0 + u * (dq1 - dq0)))
            gap = np.where(cross, np.maximum(gap, diff), gap)
    return gap


def overlapping_triangles(uv, depth, group, welded_triangles, triangle_face, depth_tolerance):
    """Every pair of triangles of one chart whose interiors overlap in projection.

    The exhaustive check (all candidate pairs from the grid, exact separating
    axis test): slower than :func:`fold_conflicts`, so the tests use it as the
    independent judge of injectivity.

    Parameters
    ----------
    uv : (t, 3, 2) float64
        Corners projected on each triangle's chart plane.
    depth : (t, 3) float64
        Corner depth along the chart's signed axis.
    group : (t,) int
        Chart of each triangle (``-1``: not in a chart on this axis, or degenerate).
    welded_triangles : (t, 3) int
        Pairs sharing a welded vertex are left out (they meet there).
    triangle_face : (t,) int
        Pairs of one face are left out (a face cannot be split).
    depth_tolerance : float
        Overlaps whose depths differ by no more than this are the same surface
        (coplanar duplicates), not a fold.

    Returns
    -------
    (p, 2) int64 triangle pairs, ``i < j``, sorted.
    """
    pairs = candidate_pairs(uv, group)
    if not len(pairs):
        return pairs
    low, high = corner_min(uv), corner_max(uv)
    a, b = pairs[:, 0], pairs[:, 1]
    boxes_touch = ((low[a] <= high[b]) & (low[b] <= high[a])).all(axis=1)
    pairs = pairs[boxes_touch & (triangle_face[a] != triangle_face[b])]
    a, b = pairs[:, 0], pairs[:, 1]
    shares_vertex = (welded_triangles[a][:, :, None] == welded_triangles[b][:, None, :]).any(axis=(1, 2))
    pairs = pairs[~shares_vertex]
    a, b = pairs[:, 0], pairs[:, 1]
    touching = ~separated(uv[a], uv[b], 0.0)
    pairs, a, b = pairs[touching], a[touching], b[touching]
    if not len(pairs):
        return pairs
    gap = overlap_depth_gap(uv[a], depth[a], uv[b], depth[b])
    return pairs[gap > depth_tolerance]


def overwound_fans(uv, group, welded_triangles, live, fan_vertices=None):
    """Fans of chart triangles around one vertex whose angles add up to more than a full turn.

    Parameters
    ----------
    uv : (t, 3, 2) float64, group : (t,) int64, welded_triangles : (t, 3) int64
    live : (k,) int64, the chart triangles to look at
    fan_vertices : (w,) bool, optional
        Only fans around these welded vertices are looked at.

    Returns
    -------
    vertex : (f,) int64, the welded vertex of each overwound fan
    members : (f, 2) int64, two of its triangles that overlap: the first and
        the one where the running angle passes 360 degrees
    """
    vertex = welded_triangles[live]                                          # (k, 3)
    keep = np.ones(vertex.shape, dtype=bool) if fan_vertices is None else fan_vertices[vertex]
    touched = keep.any(axis=1)                  # angles only of triangles with a corner looked at
    angle = triangle_angles(uv[live[touched]])[keep[touched]]
    triangle, vertex = np.repeat(live, 3)[keep.ravel()], vertex[keep]
    if not len(vertex):
        return np.zeros(0, dtype=np.int64), np.zeros((0, 2), dtype=np.int64)
    order = sort_order(group[triangle], vertex)
    v_sorted, g_sorted = vertex[order], group[triangle][order]
    change = np.ones(len(order), dtype=bool)
    change[1:] = (v_sorted[1:] != v_sorted[:-1]) | (g_sorted[1:] != g_sorted[:-1])
    fan_starts = np.concatenate((np.flatnonzero(change), [len(order)]))
    total = np.add.reduceat(angle[order], fan_starts[:-1])
    fans = np.flatnonzero(total > 2.0 * np.pi * (1.0 + 1e-6))
    first, length = fan_starts[fans], fan_starts[fans + 1] - fan_starts[fans]
    passed = np.zeros(len(fans), dtype=np.int64)
    # Each fan's running angle, as rows padded with zeros: a row's cumsum adds the fan's own angles in their
    # order, as a cumsum of the fan alone would.  Fans of similar length share a block, so padding at most
    # doubles the entries however long the longest fan is.
    size_class = np.floor(np.log2(np.maximum(length, 1))).astype(np.int64)
    for size in np.unique(size_class):
        rows = np.flatnonzero(size_class == size)
        column = np.arange(int(length[rows].max()))
        inside = column < length[rows, None]
        position = np.where(inside, first[rows, None] + column, 0)
        running = np.cumsum(np.where(inside, angle[order[position]], 0.0), axis=1)
        passed[rows] = np.minimum(np.count_nonzero(inside & (running < 2.0 * np.pi), axis=1), length[rows] - 1)
    members = np.stack([triangle[order[first]], triangle[order[first + passed]]], axis=1)
    return v_sorted[first], members.astype(np.int64)


def overlapping_wedges(uv, group, welded_triangles, live, pinch_keys, fan_vertices=None):
    """Chart triangles around one vertex, in two or more wedges, whose angles overlap.

    Where a chart touches itself at a vertex (its triangles there form
    separate wedges, as where a scan's pole or a pinched rim meets itself),
    two wedges can overlap while the angles add up to less than a full turn,
    which :func:`overwound_fans` does not see.  Each triangle covers the
    directions from its corner at the vertex counter-clockwise (every chart
    triangle faces the axis) through its angle there; sorted by the first
    direction, a triangle overlaps the next one when the next starts before
    it ends (and the last the first, a full turn on).

    Parameters
    ----------
    uv, group, welded_triangles, live
        As for :func:`overwound_fans`.
    pinch_keys : (p,) int64, sorted
        ``group * vertex_count + vertex`` of the vertices to look at (four or
        more boundary sides of the chart meet there).
    fan_vertices : (w,) bool, optional
        Only these welded vertices are looked at.

    Returns
    -------
    vertex : (k,) int64, members : (k, 2) int64, one overlapping pair per entry
    """
    empty = np.zeros(0, dtype=np.int64), np.zeros((0, 2), dtype=np.int64)
    if not len(pinch_keys) or not len(live):
        return empty
    vertex_count = int(welded_triangles.max()) + 1
    corner_vertex = welded_triangles[live]                                     # (k, 3)
    # only corners at a vertex the keys name are looked up (np.isin sorted every corner's key, at 1M ~0.5 s)
    named = np.zeros(vertex_count, dtype=bool)
    named[pinch_keys % vertex_count] = True
    if fan_vertices is not None:
        named &= fan_vertices[:vertex_count]
    triangle_index, corner = np.nonzero(named[corner_vertex])
    key = group[live[triangle_index]] * vertex_count + corner_vertex[triangle_index, corner]
    matched = pinch_keys[np.minimum(np.searchsorted(pinch_keys, key), len(pinch_keys) - 1)] == key
    if np.count_nonzero(matched) < 2:
        return empty
    triangle, corner, key = live[triangle_index[matched]], corner[matched], key[matched]
    at = uv[triangle, corner]
    toward = uv[triangle, (corner + 1) % 3] - at
    start = np.mod(np.arctan2(toward[:, 1], toward[:, 0]), 2.0 * np.pi)
    width = triangle_angles(uv[triangle])[np.arange(len(triangle)), corner]
    order = np.lexsort((start, key))
    triangle, key, start, width = triangle[order], key[order], start[order], width[order]
    starts = group_starts(key)
    first, last = starts[:-1], starts[1:] - 1
    following = np.arange(1, len(key) + 1)
    following[last] = first                               # the last one's next is the first, a turn on
    turn = np.zeros(len(key))
    turn[last] = 2.0 * np.pi
    overlap = start[following] + turn < start + width - ANGLE_TOLERANCE
    overlap &= following != np.arange(len(key))                      # a vertex with one triangle there
    pairs = np.stack([triangle[overlap], triangle[following[overlap]]], axis=1)
    return key[overlap] % vertex_count, pairs


#: Two wedges at a vertex overlapping by less than this (radians) only touch (rounding).
ANGLE_TOLERANCE = 1e-9


class FoldMemory:
    """What :func:`fold_conflicts` learnt of one axis's charts, for the next round after a split.

    Splitting a chart keeps every boundary side a boundary side (of the piece
    holding its triangle), and whether two boundary sides conflict depends on
    the two sides alone.  So after a split only the new boundary sides (the
    cuts) need pairing up; the conflicts found before stay conflicts while
    both sides stay in one chart.  Nor does a split make a fan turn further
    or two wedges at a vertex overlap more, so later rounds look for those
    only around the vertices where the first round found them.

    Parameters
    ----------
    triangle_count : int
    """

    def __init__(self, triangle_count):
        self.boundary_side = np.zeros((triangle_count, 3), dtype=bool)   # sides paired up before
        self.conflicts = np.zeros((0, 2), dtype=np.int64)                 # boundary conflicts, triangle pairs
        self.fan_vertices = None                                          # where the first round found fans
        self.rounds = 0


def fold_conflicts(uv, depth, group, welded_triangles, triangle_face, depth_tolerance, touch, margin=0.0, slope=None,
                   memory=None, order=None):
    """Triangle pairs that keep a chart from being injective, found from its boundary.

    Every triangle of a chart faces the chart's axis, so the projection is an
    orientation-preserving immersion wherever each vertex's fan turns once; an
    immersion of a compact surface into the plane that is injective on its
    boundary is injective everywhere.  So it suffices to check, per chart:

    * boundary edges (sides used by one chart triangle) that come within
      ``touch`` (or ``margin``) of each other in 2D, where their depths differ
      by more than the tolerance plus what the slopes explain;
    * vertices whose fan of chart triangles turns more than 360 degrees, or
      whose separate wedges of chart triangles overlap;
    * edges shared by three or more chart triangles, two on the same side,
      and edges whose two chart triangles both run them the same way
      (winding flipped across them), which puts both on one side.

    Boundaries are O(sqrt(n)) edges for well-shaped charts, so this costs
    O(n log n) with a small constant, unlike testing all nearby triangle pairs.

    Parameters
    ----------
    uv, depth, group, welded_triangles, triangle_face
        As for :func:`overlapping_triangles`.
    depth_tolerance : float or (t,) float
        Depth difference that still counts as one surface (per triangle when
        meshes of different sizes are baked together).
    touch : float or (t,) float
        2D distance treated as contact (e.g. coincident boundaries of stacked layers).
    margin : float
        Also report distant surfaces closer than this in 2D (about two texels).
    slope : (t,) float, optional
        |d depth / d uv| of each triangle.
    memory : FoldMemory, optional
        Kept between the rounds of one axis (the same ``uv``, ``depth``,
        tolerances and margin, each round's charts pieces of the last's
        conflicting ones): boundary sides already paired up are not paired
        again, and overwound fans and overlapping wedges are looked for only
        around the vertices where the first round found them.
    order : MeshOrder, optional
        :func:`.sides.mesh_order` of ``welded_triangles``: a caller that checks
        one mesh several times sorts it once (sorted here if not given).

    Returns
    -------
    (p, 2) int64 triangle pairs, ``i < j``, unique; one pair per problem is
    enough for the caller to split the chart between them.
    """
    live = np.flatnonzero(group >= 0)
    if len(live) < 2:
        return np.zeros((0, 2), dtype=np.int64)
    slope = np.zeros(len(uv)) if slope is None else slope
    depth_tolerance = np.broadcast_to(np.asarray(depth_tolerance, dtype=np.float64), (len(uv),))
    touch = np.broadcast_to(np.asarray(touch, dtype=np.float64), (len(uv),))
    sides = chart_sides(group, welded_triangles, live, order)
    later = memory is not None and memory.rounds > 0         # a round after the first, with what it found
    found = [_boundary_conflicts(uv, depth, group, triangle_face, sides, depth_tolerance, touch, margin, slope,
                                 memory, later)]
    found += _fan_conflicts(uv, depth, group, welded_triangles, live, sides, depth_tolerance, memory, later)
    found.append(_shared_side_conflicts(uv, depth, triangle_face, sides, depth_tolerance))
    return unique_pairs(np.concatenate(found))


def _boundary_conflicts(uv, depth, group, triangle_face, sides, depth_tolerance, touch, margin, slope, memory,
                        later):
    """1. Boundary sides of one chart that touch or come within the margin, their depths apart by more than
    the tolerance and the slopes explain: (p, 2) triangle pairs (:func:`fold_conflicts`)."""
    boundary = sides.boundary
    b_tri, b_corner = sides.tri[boundary], sides.corner[boundary]
    seg = np.stack([uv[b_tri, b_corner], uv[b_tri, (b_corner + 1) % 3]], axis=1)     # (b, 2, 2)
    seg_depth = np.stack([depth[b_tri, b_corner], depth[b_tri, (b_corner + 1) % 3]], axis=1)
    touch_most = float(touch[np.flatnonzero(group >= 0)].max())
    fresh = None                                 # sides not paired up in an earlier round (None: all)
    boundary_hits = np.zeros((0, 2), dtype=np.int64)
    if later:
        fresh = ~memory.boundary_side[b_tri, b_corner]
        a, b = memory.conflicts[:, 0], memory.conflicts[:, 1]
        boundary_hits = memory.conflicts[(group[a] >= 0) & (group[a] == group[b])]
    # Every boundary conflict needs a depth gap above the tolerance: a chart whose boundary is flatter than
    # that (a face of a box, a wall) has none, and its sides need no pairing up.
    seg_group = without_flat_groups(group[b_tri], seg_depth, depth_tolerance[b_tri])
    if margin > 4.0 * touch_most:
        # Sides that touch, and sides within the margin whose depths spread by more than the margin (a
        # conflict there needs that much): the same pairs that can conflict, from far fewer candidates.
        # Quiet sides (an interior's boxes, flat or not) cannot be in such a pair at all; along a rough
        # boundary (a scan's) most sides are loud, but their close neighbours are close in depth too.
        loud_group = without_quiet_sides(seg, seg_depth, seg_group, margin)
        pairs = unique_rows(np.concatenate([
            candidate_pairs(seg, seg_group, 2.0 * touch_most, query=fresh),
            steep_pairs(seg, seg_depth, loud_group, slope[b_tri], margin, query=fresh)]))
    else:
        pairs = candidate_pairs(seg, seg_group, max(touch_most, margin), query=fresh)
    if len(pairs):
        a, b = may_conflict(seg, seg_depth, pairs, slope[b_tri], touch_most, margin)
        b_low, b_high = sides.low[boundary], sides.high[boundary]
        ends_a = np.stack([b_low[a], b_high[a]], 1)
        ends_b = np.stack([b_low[b], b_high[b]], 1)
        shared = (ends_a[:, :, None] == ends_b[:, None, :]).any(axis=(1, 2))
        keep = ~shared & (triangle_face[b_tri[a]] != triangle_face[b_tri[b]])
        a, b = a[keep], b[keep]
        distance, s, t = segment_distance(seg[a, 0], seg[a, 1], seg[b, 0], seg[b, 1])
        depth_a = seg_depth[a, 0] + s * (seg_depth[a, 1] - seg_depth[a, 0])
        depth_b = seg_depth[b, 0] + t * (seg_depth[b, 1] - seg_depth[b, 0])
        tri_a, tri_b = b_tri[a], b_tri[b]
        explained = (np.maximum(depth_tolerance[tri_a], depth_tolerance[tri_b])
                     + distance * 2.0 * np.maximum(slope[tri_a], slope[tri_b]))
        touching = distance <= np.minimum(touch[tri_a], touch[tri_b])
        # Within the margin but not touching: a conflict only between surfaces the margin apart in depth too.
        # Closer than that, bilinear filtering mixes AO of points a few texels apart on one rough surface,
        # as it does anywhere; a ragged boundary of a noisy scan is not two surfaces.
        near = (distance <= margin) & (margin > 0)
        depth_gap = np.abs(depth_a - depth_b)
        hit = (touching & (depth_gap > explained)) | (near & (depth_gap > explained + margin))
        boundary_hits = np.concatenate([boundary_hits, np.stack([b_tri[a][hit], b_tri[b][hit]], 1)])
    if memory is not None:
        memory.boundary_side[b_tri, b_corner] = True
        memory.conflicts = boundary_hits
        memory.rounds += 1
    return boundary_hits


def _fan_conflicts(uv, depth, group, welded_triangles, live, sides, depth_tolerance, memory, later):
    """2. Vertices whose fan turns more than once, or where wedges of the chart overlap (only where four
    boundary sides of one chart or more meet can it have two wedges there): [fan pairs, wedge pairs]."""
    fan_vertices = memory.fan_vertices if later else None
    fan_vertex, fan_pairs = overwound_fans(uv, group, welded_triangles, live, fan_vertices)
    vertex_count = int(welded_triangles.max()) + 1
    b_tri = sides.tri[sides.boundary]
    ends = np.concatenate([sides.low[sides.boundary], sides.high[sides.boundary]])
    keys, meeting = np.unique(np.concatenate([group[b_tri], group[b_tri]]) * vertex_count + ends,
                              return_counts=True)
    wedge_vertex, wedge_pairs = overlapping_wedges(uv, group, welded_triangles, live, keys[meeting >= 4],
                                                   fan_vertices)
    one, two = wedge_pairs[:, 0], wedge_pairs[:, 1]
    tolerance = np.maximum(depth_tolerance[one], depth_tolerance[two])
    apart = overlap_depth_gap(uv[one], depth[one], uv[two], depth[two], closed=True) > tolerance
    if memory is not None and not later:
        memory.fan_vertices = np.zeros(vertex_count, dtype=bool)
        memory.fan_vertices[np.concatenate([fan_vertex, wedge_vertex[apart]])] = True
    return [fan_pairs, wedge_pairs[apart]]


def _shared_side_conflicts(uv, depth, triangle_face, sides, depth_tolerance):
    """3. Sides shared by 3+ chart triangles: two of them on the same side overlap.  All such pairs of all
    these sides at once: a non-manifold chart (an interior's touching boxes) has thousands.  A side of two
    chart triangles that both run it the same way (winding flipped across it, as in a scan's patches or a
    cap put on backwards) has both on one side too: every chart triangle faces the axis, so both turn
    counter-clockwise in the chart's plane.  (p, 2) triangle pairs."""
    tri, corner, starts, uses = sides.tri, sides.corner, sides.starts, sides.uses
    same_way = np.zeros(len(uses), dtype=bool)
    pair_start = starts[:-1][uses == 2]
    same_way[uses == 2] = sides.forward[pair_start] == sides.forward[pair_start + 1]
    shared = (uses > 2) | same_way
    shared_starts, shared_uses = starts[:-1][shared], uses[shared]
    if not len(shared_starts):
        return np.zeros((0, 2), dtype=np.int64)
    pairs = pairs_within_groups(np.concatenate([[0], np.cumsum(shared_uses)]))
    lead = np.repeat(shared_starts, shared_uses)         # each side's first member gives the edge's direction
    position = lead + index_in_runs(shared_uses)
    members, side_corner = tri[position], corner[position]
    edge_a = uv[tri[lead], corner[lead]]
    edge_b = uv[tri[lead], (corner[lead] + 1) % 3]
    third = uv[members, (side_corner + 2) % 3]
    direction = edge_b - edge_a
    side = np.sign(direction[:, 0] * (third[:, 1] - edge_a[:, 1]) - direction[:, 1] * (third[:, 0] - edge_a[:, 0]))
    one, two = members[pairs[:, 0]], members[pairs[:, 1]]
    same_side = (side[pairs[:, 0]] == side[pairs[:, 1]]) & (triangle_face[one] != triangle_face[two])
    one, two = one[same_side], two[same_side]
    tolerance = np.maximum(depth_tolerance[one], depth_tolerance[two])
    folded = overlap_depth_gap(uv[one], depth[one], uv[two], depth[two], closed=True) > tolerance
    return np.stack([one[folded], two[folded]], axis=1)
