"""An independent judge of 2D triangle layouts for the tests: which pairs come close, which overlap, how far
apart two triangles are.  Brute force over every pair of a group, with its own geometry; it shares no code with
``core/charts/overlap.py``, ``core/charts/candidates.py`` or ``core/arrays/geometry2d.py``, whose answers it checks."""

import numpy as np

#: Pairs are tested this many at a time (bounds memory).
BLOCK = 1 << 20


def pairs_in_groups(group):
    """Every pair ``i < j`` (p, 2) of items with the same group id (``-1`` left out), in blocks of pairs."""
    order = np.argsort(group, kind="stable")
    sorted_group = group[order]
    starts = np.flatnonzero(np.r_[True, sorted_group[1:] != sorted_group[:-1]])
    ends = np.r_[starts[1:], len(order)]
    for start, end in zip(starts, ends):
        if sorted_group[start] < 0 or end - start < 2:
            continue
        members = order[start:end]
        i, j = np.triu_indices(len(members), k=1)
        for first in range(0, len(i), BLOCK):
            yield np.stack([members[i[first:first + BLOCK]], members[j[first:first + BLOCK]]], axis=1)


def _sorted_pairs(pairs):
    pairs = np.sort(np.asarray(pairs, dtype=np.int64).reshape(-1, 2), axis=1)
    return pairs[np.lexsort((pairs[:, 1], pairs[:, 0]))]


def _box_gap(low, high, a, b):
    return np.maximum(low[b] - high[a], low[a] - high[b]).max(axis=1)


def boxes_within_brute(shapes, group, margin):
    """Every pair of shapes (k, c, 2) of one group whose bounding boxes come within ``margin``: (p, 2), i < j,
    sorted, from every pair of each group (small inputs)."""
    low, high = shapes.min(axis=1), shapes.max(axis=1)
    found = [np.zeros((0, 2), dtype=np.int64)]
    for pairs in pairs_in_groups(group):
        found.append(pairs[_box_gap(low, high, pairs[:, 0], pairs[:, 1]) <= margin])
    return _sorted_pairs(np.concatenate(found))


def boxes_within(shapes, group, margin):
    """The same pairs as :func:`boxes_within_brute`, by sweep and prune along x (large inputs): shapes sorted by
    their boxes' low x, each paired with the following ones whose low x is within its high x plus the margin."""
    low, high = shapes.min(axis=1), shapes.max(axis=1)
    live = np.flatnonzero(group >= 0)
    if not len(live):
        return np.zeros((0, 2), dtype=np.int64)
    order = live[np.argsort(low[live, 0], kind="stable")]
    sorted_low = low[order, 0]
    reach = np.searchsorted(sorted_low, high[order, 0] + margin, side="right")
    found = [np.zeros((0, 2), dtype=np.int64)]
    step = max(1, BLOCK // max(1, int(np.mean(reach - np.arange(len(order)))) + 1))
    for first in range(0, len(order), step):
        rows = np.arange(first, min(first + step, len(order)))
        counts = np.maximum(reach[rows] - rows - 1, 0)
        i = np.repeat(rows, counts)
        j = i + 1 + (np.arange(counts.sum()) - np.repeat(np.cumsum(counts) - counts, counts))
        a, b = order[i], order[j]
        keep = (group[a] == group[b]) & (_box_gap(low, high, a, b) <= margin)
        found.append(np.stack([a[keep], b[keep]], axis=1))
    return _sorted_pairs(np.concatenate(found))


def _cross(o, a, b):
    return (a[..., 0] - o[..., 0]) * (b[..., 1] - o[..., 1]) - (a[..., 1] - o[..., 1]) * (b[..., 0] - o[..., 0])


def _inside(point, triangle, slack):
    """``point`` (k, 2) strictly inside ``triangle`` (k, 3, 2) by more than ``slack`` (signed, in area units)."""
    a, b, c = triangle[:, 0], triangle[:, 1], triangle[:, 2]
    sign = np.sign(_cross(a, b, c))
    d = [sign * _cross(p, q, point) for p, q in ((a, b), (b, c), (c, a))]
    return (d[0] > slack) & (d[1] > slack) & (d[2] > slack)


def _edge_pairs(first, second):
    """For each edge of ``first`` against each edge of ``second`` (k, 3, 2): ``(p0, p1, d1, d2, d3, d4)``, the
    first's edge and the signed areas of each edge's ends against the other edge's line."""
    for p in range(3):
        p0, p1 = first[:, p], first[:, (p + 1) % 3]
        for q in range(3):
            q0, q1 = second[:, q], second[:, (q + 1) % 3]
            yield p0, p1, _cross(q0, q1, p0), _cross(q0, q1, p1), _cross(p0, p1, q0), _cross(p0, p1, q1)


def interiors_overlap(first, second, slack=1e-12):
    """(k,) bool: the open interiors of triangle pairs (k, 3, 2) share a region (touching edges do not count).

    Two triangles' interiors meet when an edge of one properly crosses an edge
    of the other, or a corner or the centre of one lies inside the other.
    """
    meet = np.zeros(len(first), dtype=bool)
    for _, _, d1, d2, d3, d4 in _edge_pairs(first, second):
        meet |= (d1 * d2 < -slack) & (d3 * d4 < -slack)
    for one, other in ((first, second), (second, first)):
        meet |= _inside(one.mean(axis=1), other, slack)
        for corner in range(3):
            meet |= _inside(one[:, corner], other, slack)
    return meet


def _point_segment(point, start, end):
    direction = end - start
    length2 = (direction * direction).sum(axis=1)
    along = np.clip(((point - start) * direction).sum(axis=1) / np.where(length2 > 0, length2, 1.0), 0.0, 1.0)
    gap = start + along[:, None] * direction - point
    return np.sqrt((gap * gap).sum(axis=1))


def triangle_distance(first, second):
    """(k,) distance between 2D triangle pairs (k, 3, 2): 0 where they overlap or touch, else the least
    distance from a corner of one to an edge of the other."""
    distance = np.full(len(first), np.inf)
    for one, other in ((first, second), (second, first)):
        for corner in range(3):
            for edge in range(3):
                distance = np.minimum(distance, _point_segment(one[:, corner], other[:, edge],
                                                               other[:, (edge + 1) % 3]))
    return np.where(interiors_overlap(first, second, 0.0), 0.0, distance)


def overlap_point(first, second):
    """A point (k, 2) in the overlap of each pair of overlapping triangles: the mean of the corners of each that
    lie in the other and of their edges' crossings (the overlap is convex, so the mean is in it)."""
    total = np.zeros((len(first), 2))
    count = np.zeros(len(first))
    for one, other in ((first, second), (second, first)):
        for corner in range(3):
            inside = _inside(one[:, corner], other, -1e-12)
            total += np.where(inside[:, None], one[:, corner], 0.0)
            count += inside
    for p0, p1, d1, d2, d3, d4 in _edge_pairs(first, second):
        crossing = (d1 * d2 < 0) & (d3 * d4 < 0)
        t = d1 / np.where(crossing, d1 - d2, 1.0)
        total += np.where(crossing[:, None], p0 + t[:, None] * (p1 - p0), 0.0)
        count += crossing
    return total / np.maximum(count, 1)[:, None]


def depth_at(point, triangle, depth):
    """Depth (k,) at ``point`` (k, 2) on the planes of ``triangle`` (k, 3, 2) with corner ``depth`` (k, 3)."""
    a, b, c = triangle[:, 0], triangle[:, 1], triangle[:, 2]
    area = _cross(a, b, c)
    area = np.where(np.abs(area) > 0, area, np.inf)
    wa, wb = _cross(point, b, c) / area, _cross(a, point, c) / area
    return wa * depth[:, 0] + wb * depth[:, 1] + (1.0 - wa - wb) * depth[:, 2]
