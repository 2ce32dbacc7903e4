"""Which shapes of one chart to compare in 2D: pairs from a uniform grid, and what rules pairs out early.

Each shape is listed in the grid cells its box touches, so the cost is
O(n log n) for any mesh whose shapes are not wildly different in size,
never O(n²).  The filters for boundary sides (:func:`.overlap.fold_conflicts`)
only leave out pairs that cannot be a conflict there.
"""

import numpy as np

from ..arrays.geometry2d import boxes_of_groups, corner_max, corner_min
from ..arrays.graph import group_starts, index_in_runs, pairs_within_groups, sort_order


#: A box more than this many grid cells long is a giant (a spike to a stray vertex):
#: :func:`giants_clipped` keeps it to where the rest of its group is.
GIANT_CELLS = 1024


def giants_clipped(low, high, group, cell, grow=0.0):
    """Boxes ``low, high`` (n, 2) with each giant (more than :data:`GIANT_CELLS` ``cell`` s long) cut down to
    the box of the other boxes of its ``group`` (n,) int >= 0 that are no giants, grown by ``grow``.

    No overlap of a giant with a box of its group that is no giant (grown by
    ``grow``) is lost: it lies inside that box.  Two giants must be compared
    by their whole boxes (:func:`giant_pairs`).  A giant with no other box of
    its group within reach becomes a point near the other boxes (an extra
    candidate, if any, is only tested).  Without this, one spike to a vertex 10^10 out lists itself in
    10^12 cells.

    Returns
    -------
    low, high : (n, 2) float64; giant : (n,) bool
    """
    giant = (high - low).max(axis=1) > GIANT_CELLS * cell
    if not giant.any():
        return low, high, giant
    count = int(group.max()) + 1
    rest_low, rest_high = boxes_of_groups(low[~giant], high[~giant], group[~giant], count)
    index = np.flatnonzero(giant)
    where = group[index]
    new_low = np.maximum(low[index], rest_low[where] - grow)
    new_high = np.minimum(high[index], rest_high[where] + grow)
    apart = (new_low > new_high).any(axis=1)
    # anywhere near the rest will do (a false candidate is only tested); far out, its cell would not fit int64
    near = np.clip(low[index[apart]], low[~giant].min(axis=0), high[~giant].max(axis=0)) if (~giant).any() else 0.0
    new_low[apart] = new_high[apart] = near
    low, high = low.copy(), high.copy()
    low[index], high[index] = new_low, new_high
    return low, high, giant


def giant_pairs(low, high, group, giant):
    """(p, 2) int64 pairs ``i < j`` of giants (``giant`` (n,) bool) of one ``group`` whose whole boxes
    ``low, high`` (n, 2) meet: all pairs of each group's giants, tested (giants are few)."""
    index = np.flatnonzero(giant)
    index = index[np.argsort(group[index], kind="stable")]
    i, j = index[pairs_within_groups(group_starts(group[index])).T]
    meet = ((low[i] <= high[j]) & (low[j] <= high[i])).all(axis=1)
    return np.stack([np.minimum(i, j)[meet], np.maximum(i, j)[meet]], axis=1)


def box_cells(low, high, origin, cell):
    """The grid cells each 2D box touches, one entry per (box, cell).

    Parameters
    ----------
    low, high : (n, 2) float64, box corners
    origin : (2,) float64, the grid's corner; cell : float, its cell size

    Returns
    -------
    first, last : (n, 2) int64, each box's lowest and highest cell
    entry : (k,) int64, the box of each entry; cell_x, cell_y : (k,) int64, its cell
    """
    first = np.floor((low - origin) / cell).astype(np.int64)
    last = np.floor((high - origin) / cell).astype(np.int64)
    span = last - first + 1
    count = span[:, 0] * span[:, 1]
    entry = np.repeat(np.arange(len(low), dtype=np.int64), count)
    local = index_in_runs(count)
    return first, last, entry, first[entry, 0] + local % span[entry, 0], first[entry, 1] + local // span[entry, 0]


def candidate_pairs(uv, group, margin=0.0, query=None, depth=None, spread=0.0, most=None):
    """Pairs of shapes of the same group whose 2D boxes come within ``margin``.

    Parameters
    ----------
    uv : (t, c, 2) float64
        Projected corners of each shape (triangles: c = 3, segments: c = 2).
    group : (t,) int
        Chart of each triangle; ``-1`` triangles are left out.
    margin : float
        Extra distance, in ``uv`` units: boxes closer than this along both
        axes pair up.
    query : (t,) bool, optional
        Only pairs with at least one of these shapes (the grid cells no query
        shape touches are never paired up).
    depth : (t, c) float64, optional
        Depth of each corner; with it, only pairs whose depth spread
        ``max(high_i - low_j, high_j - low_i)`` exceeds ``spread`` (the most
        their depths can differ).  Each cell's shapes are then paired by
        depth, never all with all: a fold check across a margin wants the
        few pairs far apart in depth among the many neighbours along one
        boundary.
    spread : float
    most : int, optional
        With ``depth``: None instead of the pairs if the cells would have more than this many pairs to test.

    Returns
    -------
    (p, 2) int64 shape pairs, ``i < j``, each once, sorted.
    """
    live = np.flatnonzero(group >= 0)
    if len(live) < 2:
        return np.zeros((0, 2), dtype=np.int64)
    low = corner_min(uv[live]) - 0.5 * margin
    high = corner_max(uv[live]) + 0.5 * margin
    typical = float(np.median((high - low).max(axis=1)))
    whole_low, whole_high = low, high
    low, high, giant = giants_clipped(low, high, group[live], max(typical, 1e-300))
    extent = high - low
    # Cells about the size of a typical triangle, but never so small that the
    # few huge triangles of a mixed mesh fill millions of cells.
    cell = max(typical, float(np.sqrt((extent[:, 0] * extent[:, 1]).sum() / (4.0 * len(live)))), 1e-300)
    first, last, entry, cell_x, cell_y = box_cells(low, high, low.min(axis=0), cell)
    if query is not None:
        # only the cells a query shape touches (one int64 key per group and cell)
        span_x = int(last[:, 0].max()) + 1
        span_y = int(last[:, 1].max()) + 1
        key = (group[live][entry] * span_y + cell_y) * span_x + cell_x
        touched = np.isin(key, key[query[live][entry]])
        entry, cell_x, cell_y = entry[touched], cell_x[touched], cell_y[touched]
    order = sort_order(group[live][entry], cell_x, cell_y)
    entry, cell_x, cell_y = entry[order], cell_x[order], cell_y[order]
    key_change = np.ones(len(entry), dtype=bool)
    key_change[1:] = (
        (cell_x[1:] != cell_x[:-1]) | (cell_y[1:] != cell_y[:-1])
        | (group[live][entry[1:]] != group[live][entry[:-1]]))
    starts = np.concatenate((np.flatnonzero(key_change), [len(entry)]))
    if depth is None:
        here, there = pairs_within_groups(starts).T.copy()
    else:
        paired = _pairs_apart_in_depth(entry, cell_x, cell_y, starts, depth[live], spread, most)
        if paired is None:
            return None
        entry, cell_x, cell_y, here, there = paired
    # Each pair once, from the one cell both boxes hold whose corner is the larger of their low corners
    # (no sort to drop repeats), and only where the boxes themselves meet.  Each box's numbers in the
    # entries' order first: ``here`` runs in order and ``there`` stays in its cell, so reads stay close.
    first_x, first_y = first[entry, 0], first[entry, 1]
    keep = cell_x[here] == np.maximum(first_x[here], first_x[there])
    keep &= cell_y[here] == np.maximum(first_y[here], first_y[there])
    for axis in (0, 1):
        axis_low, axis_high = low[entry, axis], high[entry, axis]
        keep &= axis_low[here] <= axis_high[there]
        keep &= axis_low[there] <= axis_high[here]
    i, j = entry[here[keep]], entry[there[keep]]
    if giant.any():                     # two giants: by their whole boxes (the grid only saw them clipped)
        apart = ~(giant[i] & giant[j])
        extra = giant_pairs(whole_low, whole_high, group[live], giant)
        if depth is not None:
            d = depth[live]
            extra = extra[_spread_exceeds(d.min(axis=1), d.max(axis=1), extra[:, 0], extra[:, 1], spread)]
        i, j = np.concatenate([i[apart], extra[:, 0]]), np.concatenate([j[apart], extra[:, 1]])
    i, j = live[i], live[j]                              # i < j: a cell lists its shapes in order
    if depth is not None or giant.any():                 # ... unless it lists them by depth
        i, j = np.minimum(i, j), np.maximum(i, j)
    if query is not None:
        asked = query[i] | query[j]
        i, j = i[asked], j[asked]
    order = np.argsort(i * len(group) + j, kind="stable")
    return np.stack([i[order], j[order]], axis=1)


def _pairs_apart_in_depth(entry, cell_x, cell_y, starts, depth, spread, most=None):
    """The pairs of each cell's entries whose depth spread may exceed ``spread``, found by depth.

    A shape's depths span ``mid +- half``; two shapes' spread is
    ``|mid_i - mid_j| + half_i + half_j``.  Within a cell sorted by ``mid``,
    an entry pairs with the later ones whose ``mid`` exceeds its own by more
    than ``spread - half - (the cell's largest half)``: one range each, a
    superset of the wanted pairs, which are then picked exactly.

    Parameters
    ----------
    entry, cell_x, cell_y : (k,) int64, sorted by cell; starts : (g + 1,) int64, each cell's first entry
    depth : (n, c) float64, each shape's corner depths; spread : float

    Returns
    -------
    entry, cell_x, cell_y : (k,) int64, reordered by depth within each cell
    here, there : (p,) int64, positions of the pairs' entries (either may be first)

    None instead if there would be more than ``most`` pairs to test.
    """
    if not len(entry):
        return entry, cell_x, cell_y, entry, entry
    shallow, deep = depth.min(axis=1), depth.max(axis=1)
    mid, half = 0.5 * (shallow + deep)[entry], 0.5 * (deep - shallow)[entry]
    cell = np.repeat(np.arange(len(starts) - 1), np.diff(starts))
    order = np.lexsort((mid, cell))
    entry, cell_x, cell_y, mid, half = entry[order], cell_x[order], cell_y[order], mid[order], half[order]
    cell_half = np.maximum.reduceat(half, starts[:-1])
    # one sorted float key for (cell, mid): cells a stride apart, wider than any reach
    bottom = float(mid.min())
    width = float(mid.max()) - bottom
    stride = (2.0 * width + abs(float(spread))) or 1.0
    key = cell * stride + (mid - bottom)
    # the slack covers rounding of the key and of mid (an entry too many is dropped below, never one too few)
    slack = 8.0 * np.finfo(np.float64).eps * (len(starts) * stride + abs(bottom) + width + abs(float(spread)))
    reach = mid + (spread - half - cell_half[cell]) - slack
    first = np.searchsorted(key, cell * stride + (reach - bottom), side="right")
    position = np.arange(len(entry))
    end = starts[1:][cell]
    first = np.clip(first, position + 1, end)
    if most is not None and int((end - first).sum()) > most:
        return None
    here = np.repeat(position, end - first)
    there = np.repeat(first, end - first) + index_in_runs(end - first)
    # the depths in the cells' order: ``here`` runs in order and ``there`` stays within its cell
    keep = _spread_exceeds(shallow[entry], deep[entry], here, there, spread)
    return entry, cell_x, cell_y, here[keep], there[keep]


def _spread_exceeds(shallow, deep, a, b, spread):
    """(p,) bool: whether the depths of shapes ``a`` and ``b`` ((p,) int), each spanning ``shallow`` to
    ``deep`` ((n,) float64), spread over more than ``spread``."""
    return np.maximum(deep[a] - shallow[b], deep[b] - shallow[a]) > spread


def without_flat_groups(seg_group, seg_depth, tolerance):
    """``seg_group`` with ``-1`` for the segments of groups whose depths all lie within the least tolerance.

    Parameters
    ----------
    seg_group : (b,) int >= 0, seg_depth : (b, 2) float64, tolerance : (b,) float64

    Returns
    -------
    (b,) int64.  A depth gap between two points of such a group, interpolated
    along its segments, never exceeds the spread of their ends (a relative
    1e-12 allows for rounding), so it cannot exceed any tolerance of the group.
    """
    seg_group = np.asarray(seg_group, dtype=np.int64)
    if not len(seg_group):
        return seg_group
    count = int(seg_group.max()) + 1
    low = np.full(count, np.inf)
    high = np.full(count, -np.inf)
    least = np.full(count, np.inf)
    np.minimum.at(low, seg_group, seg_depth.min(axis=1))
    np.maximum.at(high, seg_group, seg_depth.max(axis=1))
    np.minimum.at(least, seg_group, tolerance)
    held = np.isfinite(low)                              # groups with a segment
    flat = np.zeros(count, dtype=bool)
    flat[held] = (high - low)[held] + 1e-12 * np.maximum(np.abs(high), np.abs(low))[held] < least[held]
    return np.where(flat[seg_group], -1, seg_group)


def without_quiet_sides(seg, seg_depth, seg_group, margin):
    """``seg_group`` with ``-1`` for the segments that cannot be in a conflict across ``margin``.

    Two segments within ``margin`` of each other (boxes, along both axes) hold
    points in grid cells at most one apart, for cells at least ``margin``
    wide; so their depth spread is at most the depth range of the 3 x 3
    cells around a cell the first one touches.  A segment is quiet when that
    range is at most ``margin`` around every cell it touches: no segment
    within the margin is farther than that from it in depth, and a conflict
    across the margin needs more (:func:`fold_conflicts`).

    Parameters
    ----------
    seg : (b, 2, 2) float64, seg_depth : (b, 2) float64
    seg_group : (b,) int64, ``-1`` for segments left out
    margin : float > 0

    Returns
    -------
    (b,) int64
    """
    live = np.flatnonzero(seg_group >= 0)
    if not len(live):
        return seg_group
    low, high = corner_min(seg[live]), corner_max(seg[live])
    # cells as large as candidate_pairs' (a typical segment with its margin), never smaller than the margin
    cell = 1.001 * max(margin, float(np.median((high - low).max(axis=1))) + margin)
    # a giant keeps the cells within reach of the rest of its group (its depths still count in all of
    # them); it is never quiet (two giants meet anywhere along them)
    low, high, giant = giants_clipped(low, high, seg_group[live], cell, grow=margin + 2.0 * cell)
    # every cell has its neighbours at indices >= 0
    first, last, entry, cell_x, cell_y = box_cells(low, high, low.min(axis=0) - cell, cell)
    columns, rows = int(last[:, 0].max()) + 2, int(last[:, 1].max()) + 2
    if float(seg_group.max() + 1) * columns * rows >= 2.0**62:
        return seg_group
    key = (seg_group[live][entry] * rows + cell_y) * columns + cell_x
    cells, cell_of = np.unique(key, return_inverse=True)
    cell_of = cell_of.reshape(-1)
    shallow = np.full(len(cells), np.inf)
    deep = np.full(len(cells), -np.inf)
    np.minimum.at(shallow, cell_of, seg_depth[live].min(axis=1)[entry])
    np.maximum.at(deep, cell_of, seg_depth[live].max(axis=1)[entry])
    around_shallow, around_deep = shallow.copy(), deep.copy()
    for step in (-columns - 1, -columns, -columns + 1, -1, 1, columns - 1, columns, columns + 1):
        at = np.minimum(np.searchsorted(cells, cells + step), len(cells) - 1)
        there = cells[at] == cells + step
        around_shallow[there] = np.minimum(around_shallow[there], shallow[at[there]])
        around_deep[there] = np.maximum(around_deep[there], deep[at[there]])
    loud = np.bincount(entry, weights=(around_deep - around_shallow > margin)[cell_of], minlength=len(live)) > 0
    result = seg_group.copy()
    result[live[~(loud | giant)]] = -1
    return result


def may_conflict(seg, seg_depth, pairs, seg_slope, touch, margin):
    """The candidate pairs of boundary segments that can be a conflict of :func:`fold_conflicts`.

    A conflict needs a depth gap at the closest points above what the slopes
    explain over their distance, plus the margin unless the segments touch.
    The gap is at most the spread of the two segments' depths, and the
    distance at least the gap between their boxes, so pairs whose depth
    spread is below that are no conflict (most pairs: neighbours along one
    boundary).

    Parameters
    ----------
    seg : (b, 2, 2) float64, seg_depth : (b, 2) float64, pairs : (p, 2) int, seg_slope : (b,) float64
    touch : float, the largest contact distance; margin : float

    Returns
    -------
    a, b : (k,) int64, the pairs kept
    """
    a, b = pairs[:, 0], pairs[:, 1]
    (x_low, y_low), (x_high, y_high) = corner_min(seg).T, corner_max(seg).T
    box_gap = np.maximum(np.maximum(x_low[a] - x_high[b], x_low[b] - x_high[a]),
                         np.maximum(y_low[a] - y_high[b], y_low[b] - y_high[a]))
    box_gap = np.maximum(box_gap, 0.0)
    d_low, d_high = corner_min(seg_depth), corner_max(seg_depth)
    spread = np.maximum(d_high[a] - d_low[b], d_high[b] - d_low[a])
    needed = box_gap * 2.0 * np.maximum(seg_slope[a], seg_slope[b]) + np.where(box_gap <= touch, 0.0, margin)
    keep = spread > needed
    return a[keep], b[keep]
