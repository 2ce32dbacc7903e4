"""core/charts/sides.py: a chart's sides grouped by edge, from one sort per mesh."""

import numpy as np

from seamless_ao.core.charts.sides import chart_sides, mesh_order


def _grid(n, seed):
    """An n x n grid of quads, two triangles each, with a few triangles welded to a zero-length side, and a
    chart number per triangle (-1 for some)."""
    rng = np.random.default_rng(seed)
    v = np.arange((n + 1) * (n + 1)).reshape(n + 1, n + 1)
    a, b, c, d = v[:-1, :-1].ravel(), v[:-1, 1:].ravel(), v[1:, 1:].ravel(), v[1:, :-1].ravel()
    triangles = np.concatenate([np.stack([a, b, c], 1), np.stack([a, c, d], 1)])
    triangles[rng.choice(len(triangles), 5, replace=False), 2] = triangles[0, 0]   # some sides of length zero
    collapsed = rng.choice(len(triangles), 3, replace=False)
    triangles[collapsed, 1] = triangles[collapsed, 0]
    group = rng.integers(-1, 4, len(triangles))
    return triangles, group


def _runs_by_brute_force(triangles, group):
    """(edge, chart) -> the (triangle, corner) of its sides in triangle order, from a plain loop."""
    runs = {}
    for tri in np.flatnonzero(group >= 0):
        for corner in range(3):
            start, end = triangles[tri, corner], triangles[tri, (corner + 1) % 3]
            if start != end:
                key = (min(start, end), max(start, end), group[tri])
                runs.setdefault(key, []).append((tri, corner, start < end))
    return runs


def test_chart_sides_groups_each_charts_uses_of_an_edge_in_triangle_order():
    """Against a plain loop, for two chart assignments of one mesh: sorted here, and from one order of the
    mesh shared by both calls (as make_injective shares it between its rounds)."""
    triangles, _ = _grid(12, seed=3)
    shared = mesh_order(triangles)
    for seed in (3, 4):
        group = np.random.default_rng(seed).integers(-1, 4, len(triangles))
        live = np.flatnonzero(group >= 0)
        expected = _runs_by_brute_force(triangles, group)
        for order in (None, shared):
            sides = chart_sides(group, triangles, live, order)
            assert len(sides.uses) == len(expected)
            for first, count in zip(sides.starts[:-1], sides.uses):
                members = slice(first, first + count)
                key = (sides.low[first], sides.high[first], group[sides.tri[first]])
                found = list(zip(sides.tri[members].tolist(), sides.corner[members].tolist(),
                                 sides.forward[members].tolist()))
                assert found == expected[key]
                assert (sides.low[members] == key[0]).all() and (sides.high[members] == key[1]).all()
            boundary = {(int(sides.tri[i]), int(sides.corner[i])) for i in sides.boundary}
            assert boundary == {run[0][:2] for run in expected.values() if len(run) == 1}


def test_an_edge_of_three_triangles_keeps_one_charts_two_together():
    """Three triangles at one edge, charts 0, 1, 0 in triangle order: chart 0 uses the edge twice (no
    boundary there), chart 1 once."""
    triangles = np.array([[0, 1, 2], [1, 0, 3], [0, 1, 4]])
    group = np.array([0, 1, 0])
    sides = chart_sides(group, triangles, np.arange(3))
    edge = (sides.low == 0) & (sides.high == 1)
    runs = [(sides.tri[a:b].tolist(), sides.uses[i]) for i, (a, b) in enumerate(zip(sides.starts[:-1], sides.starts[1:]))
            if edge[a]]
    assert sorted(runs) == [([0, 2], 2), ([1], 1)]
    assert set(sides.tri[sides.boundary][edge[sides.boundary]].tolist()) == {1}
