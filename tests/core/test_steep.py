"""core/charts/steep.py: the pairs of boundary segments a fold check across the margin needs, from a grid
whose cells carry the bounds of what they list."""

import numpy as np
import pytest

from seamless_ao.core.charts import steep
from seamless_ao.core.charts.candidates import candidate_pairs, may_conflict
from seamless_ao.core.charts.steep import steep_pairs

MARGIN = 0.3
#: Segments of each boundary with a fold above them.
FOLDED = 10
#: Segments across many cells.
GIANTS = 2


def _steep_boundaries(seed, count=1500):
    """Segments of a meandering rough boundary at a slope (depth follows it across the slope, as along a scan's
    chart edge at 60 degrees), a fold above part of it (the same boundary five margins deeper, half a margin away),
    a few giants across, some left out; two groups.  ``(seg, seg_depth, seg_group, seg_slope)``."""
    rng = np.random.default_rng(seed)
    x = np.cumsum(rng.uniform(0.005, 0.02, count + 1))
    y = 0.6 * np.sin(2.5 * x) + np.cumsum(rng.normal(0.0, 0.01, count + 1))
    slope = rng.uniform(1.5, 1.9, count)            # each segment's triangle's; the surface's is 1.7
    points = np.stack([x, y], axis=1)
    seg = np.stack([points[:-1], points[1:]], axis=1)                       # (count, 2, 2)
    depth = 1.7 * np.stack([y[:-1], y[1:]], axis=1) + rng.normal(0.0, 0.01, (count, 2))
    fold = seg[:FOLDED] + np.array([0.0, 0.5 * MARGIN])
    giants = rng.uniform(0.0, x[-1], (GIANTS, 2, 2))
    giants[:, :, 1] = rng.uniform(y.min(), y.max(), (GIANTS, 2))
    seg = np.concatenate([seg, fold, giants])
    seg_depth = np.concatenate([depth, depth[:FOLDED] + 5.0 * MARGIN, rng.uniform(-1.0, 1.0, (GIANTS, 2))])
    seg_slope = np.concatenate([slope, slope[:FOLDED], rng.uniform(0.5, 2.0, GIANTS)])
    seg_group = rng.integers(0, 2, len(seg))
    seg_group[rng.choice(len(seg), 40, replace=False)] = -1
    return seg, seg_depth, seg_group, seg_slope


def _wanted(seg, seg_depth, seg_group, seg_slope):
    """Every pair ``i < j`` of one group within the margin whose depths spread by more than the margin and
    what the slope explains over their gap, by brute force: a set of tuples."""
    low, high = seg.min(axis=1), seg.max(axis=1)
    shallow, deep = seg_depth.min(axis=1), seg_depth.max(axis=1)
    i, j = np.triu_indices(len(seg), 1)
    same = (seg_group[i] >= 0) & (seg_group[i] == seg_group[j])
    i, j = i[same], j[same]
    gap = np.maximum(np.maximum(low[i] - high[j], low[j] - high[i]).max(axis=1), 0.0)
    spread = np.maximum(deep[i] - shallow[j], deep[j] - shallow[i])
    keep = (gap <= MARGIN) & (spread > gap * 2.0 * np.maximum(seg_slope[i], seg_slope[j]) + MARGIN)
    return set(zip(i[keep].tolist(), j[keep].tolist()))


@pytest.mark.parametrize("seed", [0, 1, 2])
@pytest.mark.parametrize("by_depth_up_to", [0, steep.DEPTH_PAIRS_PER_SEGMENT])
def test_steep_pairs_hold_every_pair_the_fold_check_can_keep(seed, by_depth_up_to, monkeypatch):
    """Both ways (the grid of cells, forced with no pairs allowed by depth, and the default choice): every
    pair the brute force wants, only pairs of one group, each once, sorted, and with a query only pairs
    that hold one of it."""
    monkeypatch.setattr(steep, "DEPTH_PAIRS_PER_SEGMENT", by_depth_up_to)
    seg, seg_depth, seg_group, seg_slope = _steep_boundaries(seed)
    wanted = _wanted(seg, seg_depth, seg_group, seg_slope)
    assert len(wanted) > 100                        # the folds are found
    pairs = steep_pairs(seg, seg_depth, seg_group, seg_slope, MARGIN)
    assert wanted <= set(zip(*pairs.T.tolist()))
    assert (pairs[:, 0] < pairs[:, 1]).all()
    assert (seg_group[pairs[:, 0]] == seg_group[pairs[:, 1]]).all() and (seg_group[pairs[:, 0]] >= 0).all()
    order = np.lexsort((pairs[:, 1], pairs[:, 0]))
    assert np.array_equal(order, np.arange(len(pairs))) and len(np.unique(pairs, axis=0)) == len(pairs)
    query = np.random.default_rng(seed).random(len(seg)) < 0.1
    asked = steep_pairs(seg, seg_depth, seg_group, seg_slope, MARGIN, query=query)
    assert {(i, j) for i, j in wanted if query[i] or query[j]} <= set(zip(*asked.T.tolist()))
    assert (query[asked[:, 0]] | query[asked[:, 1]]).all()


@pytest.mark.parametrize("seed", [0, 1])
def test_the_grid_of_cells_tests_few_pairs_where_the_boundary_runs_steep(seed, monkeypatch):
    """Along a steep rough boundary, pairing by depth alone hands the fold check every loud pair within the
    margin; the grid hands it a small share of those, and the fold check keeps the same ones of either."""
    monkeypatch.setattr(steep, "DEPTH_PAIRS_PER_SEGMENT", 0)
    seg, seg_depth, seg_group, seg_slope = _steep_boundaries(seed)
    by_depth = candidate_pairs(seg, seg_group, MARGIN, depth=seg_depth, spread=MARGIN)
    by_cells = steep_pairs(seg, seg_depth, seg_group, seg_slope, MARGIN)
    assert len(by_cells) * 4 < len(by_depth)
    touch = 1e-9
    kept_by_depth = set(zip(*[side.tolist() for side in may_conflict(seg, seg_depth, by_depth, seg_slope, touch,
                                                                      MARGIN)]))
    kept_by_cells = set(zip(*[side.tolist() for side in may_conflict(seg, seg_depth, by_cells, seg_slope, touch,
                                                                      MARGIN)]))
    assert kept_by_cells == kept_by_depth == _wanted(seg, seg_depth, seg_group, seg_slope)


@pytest.mark.parametrize("far", [1e3, 1e12])
def test_a_spike_far_out_leaves_the_grid_of_cells_whole(far, monkeypatch):
    """A side running from the boundary to a stray vertex far out is paired with the boxes it meets, as any
    giant is, and the cells of the rest still hold every pair the fold check can keep."""
    monkeypatch.setattr(steep, "DEPTH_PAIRS_PER_SEGMENT", 0)
    seg, seg_depth, seg_group, seg_slope = _steep_boundaries(4)
    spike = np.array([[[seg[5, 0, 0], seg[5, 0, 1] + 0.5 * MARGIN], [far, far]]])
    seg = np.concatenate([seg, spike])
    seg_depth = np.concatenate([seg_depth, [[10.0 * MARGIN, 0.0]]])
    seg_slope = np.concatenate([seg_slope, [1.7]])
    seg_group = np.concatenate([seg_group, [seg_group[5]]])
    pairs = set(zip(*steep_pairs(seg, seg_depth, seg_group, seg_slope, MARGIN).T.tolist()))
    wanted = _wanted(seg, seg_depth, seg_group, seg_slope)
    assert any(len(seg) - 1 in pair for pair in wanted)
    assert wanted <= pairs
