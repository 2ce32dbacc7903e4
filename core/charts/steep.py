"""Which boundary segments of one chart to compare across the margin where the boundary runs steep
(:func:`steep_pairs`): a grid of cells, each with the box, the depths and the least slope of what it lists.

A rough boundary at 60 degrees to the axis (a scan's) has loud sides all along it: most pairs a few texels
apart spread by more than the margin in depth, so pairing by depth alone (:func:`.candidates.candidate_pairs`)
tests millions, and :func:`.candidates.may_conflict` then keeps a few thousand of them: what the slope
explains over their gap rules the rest out.  The cells let that rule work before any pair is made.
"""

import numpy as np

from ..arrays.geometry2d import corner_max, corner_min
from ..arrays.graph import group_starts, index_in_runs, unique_rows
from .candidates import candidate_pairs

#: Grid cells per margin of :func:`steep_pairs`: finer cells bound the gap of the pairs they list more tightly,
#: coarser ones leave fewer pairs of cells to test.
STEEP_CELLS_PER_MARGIN = 6
#: :func:`steep_pairs` lists a segment in at most this many cells; longer ones go to
#: :func:`.candidates.candidate_pairs`.
STEEP_MOST_CELLS = 64
#: :func:`steep_pairs` pairs by depth alone (:func:`.candidates.candidate_pairs`) while that tests at most
#: this many pairs a segment.  Below it the grid's pairs of cells cost more than the pairs of segments they
#: save (every call of the 70k scan's bake, and of the million-triangle scan's at 512²); above it (the
#: million-triangle scan's Z charts at 256²) the grid was the faster.
DEPTH_PAIRS_PER_SEGMENT = 128


def steep_pairs(seg, seg_depth, seg_group, seg_slope, margin, query=None):
    """The pairs of boundary segments of one group that :func:`.candidates.may_conflict` can keep across the
    margin.

    Parameters
    ----------
    seg : (b, 2, 2) float64, seg_depth : (b, 2) float64, seg_slope : (b,) float64 >= 0
    seg_group : (b,) int64, ``-1`` for segments left out
    margin : float > 0
    query : (b,) bool, optional: only pairs with at least one of these

    Returns
    -------
    (p, 2) int64 pairs ``i < j``, each once, sorted: every pair whose boxes come within ``margin`` (along
    both axes) and whose depth spread exceeds ``margin + 2 gap max(slope)`` (``gap`` between their boxes),
    and maybe others (:func:`.candidates.may_conflict` decides).

    Pairs are found by depth alone (:func:`.candidates.candidate_pairs`) where that tests at most
    :data:`DEPTH_PAIRS_PER_SEGMENT` pairs a segment.  Otherwise each segment is listed in the cells of a
    grid (a sixth of the margin) its box touches.  Two cells are paired up only where the box, the depths
    and the least slope of all they list allow one pair of their segments to be kept; then only their
    segments are.  A segment whose box touches more than :data:`STEEP_MOST_CELLS` cells is paired by
    :func:`.candidates.candidate_pairs`, by depth.
    """
    live = np.flatnonzero(seg_group >= 0)
    by_depth = candidate_pairs(seg, seg_group, margin, query=query, depth=seg_depth, spread=margin,
                               most=DEPTH_PAIRS_PER_SEGMENT * len(live))
    if by_depth is not None:
        return by_depth
    cell = margin / STEEP_CELLS_PER_MARGIN
    low, high = corner_min(seg[live]), corner_max(seg[live])
    first, last = np.floor((low - low.min(axis=0)) / cell), np.floor((high - low.min(axis=0)) / cell)
    giant = ((last - first + 1).prod(axis=1) > STEEP_MOST_CELLS) | ~np.isfinite(first).all(axis=1)
    if not giant.all():                                     # the others' cells from 0 (a spike may lie far out)
        corner = first[~giant].min(axis=0)
        first, last = first - corner, last - corner
    reach = int(np.ceil(margin / cell)) + 2                 # cells apart, at most, of two a pair lists within it
    columns = float(last[~giant, 0].max(initial=0)) + 2 * reach + 1
    rows = float(last[~giant, 1].max(initial=0)) + 2 * reach + 1
    if float(seg_group.max(initial=0) + 1) * columns * rows >= 2.0**62:
        giant[:] = True                                     # far-flung: all by the grid of boxes
    found = [np.zeros((0, 2), dtype=np.int64)]
    if giant.any():
        asked = np.zeros(len(seg_group), dtype=bool)
        asked[live[giant]] = True
        found.append(candidate_pairs(seg, seg_group, margin, query=asked, depth=seg_depth, spread=margin))
    if not giant.all():
        shape, low, high = live[~giant], low[~giant], high[~giant]
        first, last = first[~giant].astype(np.int64), last[~giant].astype(np.int64)
        span = last - first + 1
        count = span[:, 0] * span[:, 1]
        entry = np.repeat(np.arange(len(shape)), count)
        local = index_in_runs(count)
        key = ((seg_group[shape][entry] * int(rows) + first[entry, 1] + local // span[entry, 0] + reach)
               * int(columns) + first[entry, 0] + local % span[entry, 0] + reach)
        found.append(_cell_steep_pairs(shape, entry, key, int(columns), reach, low, high, seg_depth, seg_slope,
                                       margin))
    pairs = np.concatenate(found)
    if query is not None:
        pairs = pairs[query[pairs[:, 0]] | query[pairs[:, 1]]]
    return unique_rows(pairs)


def _cell_steep_pairs(shape, entry, key, columns, reach, low, high, seg_depth, seg_slope, margin):
    """:func:`steep_pairs` of segments ``shape`` (k,) with boxes ``low, high`` (k, 2), listed as ``entry``
    (e,) in cells ``key`` (e,) int64 (``columns`` a row): cells up to ``reach`` apart are paired up where
    the box, the depths and the least slope of each (bounds of every pair they list) allow a pair to be
    kept, then their segments.  (p, 2) int64 pairs, ``i < j``, some more than once."""
    order = np.argsort(key, kind="stable")
    entry, key = entry[order], key[order]
    starts = group_starts(key)
    cells, begin = key[starts[:-1]], starts[:-1]
    d_low, d_high = seg_depth[shape].min(axis=1), seg_depth[shape].max(axis=1)
    slope = seg_slope[shape]
    # one row a cell: its box (low x, low y, -high x, -high y), its depth span (shallow, -deep) and least slope
    cell = np.minimum.reduceat(np.column_stack([low, -high, d_low, -d_high, slope])[entry], begin, axis=0)
    # each cell with the cells of the rows 0 .. reach above within reach along the row (one run each in
    # key order), itself and those after it in its own row
    position = np.arange(len(cells))
    first = [position] + [np.searchsorted(cells, cells + dy * columns - reach) for dy in range(1, reach + 1)]
    end = [np.searchsorted(cells, cells + dy * columns + reach, side="right") for dy in range(reach + 1)]
    runs = np.concatenate([e - f for f, e in zip(first, end)])
    one = np.tile(position, reach + 1).repeat(runs)
    two = np.concatenate(first).repeat(runs) + index_in_runs(runs)
    # no pair of their segments lies closer, spreads more in depth or is less steep
    a, b = cell[one], cell[two]
    keep = _steep_enough(a[:, :2], -a[:, 2:4], b[:, :2], -b[:, 2:4],
                         np.maximum(-a[:, 5] - b[:, 4], -b[:, 5] - a[:, 4]), np.maximum(a[:, 6], b[:, 6]), margin)
    one, two = one[keep], two[keep]
    size = np.diff(starts)
    count = size[one] * size[two]
    pair_cell = np.repeat(np.arange(len(one)), count)
    local = index_in_runs(count)
    a = entry[starts[one][pair_cell] + local // size[two][pair_cell]]
    b = entry[starts[two][pair_cell] + local % size[two][pair_cell]]
    keep = a != b
    a, b = a[keep], b[keep]
    keep = _steep_enough(low[a], high[a], low[b], high[b], np.maximum(d_high[a] - d_low[b], d_high[b] - d_low[a]),
                         np.maximum(slope[a], slope[b]), margin)
    i, j = shape[a[keep]], shape[b[keep]]
    return np.stack([np.minimum(i, j), np.maximum(i, j)], axis=1)


def _steep_enough(low_a, high_a, low_b, high_b, spread, slope, margin):
    """(p,) bool: boxes ``(p, 2)`` within the margin whose ``spread`` exceeds what
    :func:`.candidates.may_conflict` asks across their gap at ``slope`` (a relative 1e-9 of the margin to spare
    for rounding)."""
    gap = np.maximum(np.maximum(low_a - high_b, low_b - high_a).max(axis=1), 0.0)
    return (gap <= margin * (1.0 + 1e-9)) & (spread > gap * 2.0 * slope + margin)
