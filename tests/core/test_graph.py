"""core/arrays/graph.py: connected components against a plain search, sorting orders against numpy's lexsort,
the scatter of pairs against numpy's assignment."""

import numpy as np
import pytest

from seamless_ao.core.arrays import graph
from seamless_ao.core.arrays.graph import connected_components, sort_order


@pytest.mark.parametrize("nodes, edge_count", [(1, 0), (9, 0), (30, 12), (200, 150), (500, 2000), (300, -1)])
def test_connected_components_match_a_search_from_each_smallest_node(nodes, edge_count):
    """Against a breadth-first search from each not yet labelled node in ascending order: the same
    components, numbered in order of their smallest node, whatever the edges' order and integer type
    (self-loops and repeats included).  ``edge_count`` -1: two long paths through shuffled nodes joined
    by one edge (many rounds of hooking, the last ones with a few edges left)."""
    rng = np.random.default_rng(nodes + edge_count)
    if edge_count < 0:
        path = rng.permutation(nodes)
        edges = np.stack([path[:-1], path[1:]], axis=1)
        edges = np.concatenate([np.delete(edges, nodes // 2, axis=0)[rng.permutation(nodes - 2)],
                                edges[nodes // 2:nodes // 2 + 1]])
        edge_count = len(edges)
    else:
        edges = rng.integers(0, nodes, (edge_count, 2))
    edges = np.concatenate([edges, edges[: edge_count // 5, ::-1], np.repeat(np.arange(min(nodes, 5)), 2).reshape(-1, 2)])
    neighbours = [[] for _ in range(nodes)]
    for a, b in edges:
        neighbours[a].append(b)
        neighbours[b].append(a)
    expected = np.full(nodes, -1)
    label = 0
    for start in range(nodes):
        if expected[start] >= 0:
            continue
        expected[start], queue = label, [start]
        while queue:
            for other in neighbours[queue.pop()]:
                if expected[other] < 0:
                    expected[other] = label
                    queue.append(other)
        label += 1
    for given in (edges, edges[rng.permutation(len(edges))].astype(np.int32), edges.tolist()):
        labels = connected_components(nodes, given)
        assert labels.dtype == np.int64
        assert np.array_equal(labels, expected)


def test_an_unstable_sort_order_sorts_the_same_keys():
    """``stable=False`` may permute entries with equal keys, nothing else: the keys come out in the same
    order as the stable sort's, and every entry once."""
    rng = np.random.default_rng(3)
    keys = [rng.integers(0, 50, 20000), rng.integers(0, 7, 20000)]
    stable, unstable = sort_order(*keys), sort_order(*keys, stable=False)
    assert np.array_equal(np.sort(unstable), np.arange(20000))
    for key in keys:
        assert np.array_equal(key[stable], key[unstable])


@pytest.mark.parametrize("shuffled", [False, True], ids=["in-mesh-order", "shuffled"])
def test_sort_order_of_many_keys_is_lexsort_in_either_order(shuffled):
    """Past RADIX_FROM entries: keys along a mesh (a grid's edges) go to numpy's merge sort, the same keys
    shuffled to the radix sort; both must be lexsort's order, ties in input order."""
    side = 300
    vertex = np.arange(side * side).reshape(side, side)
    quads = np.stack([vertex[:-1, :-1], vertex[:-1, 1:], vertex[1:, 1:], vertex[1:, :-1]], axis=-1).reshape(-1, 4)
    start, end = quads.ravel(), np.roll(quads, -1, axis=1).ravel()
    keys = [np.minimum(start, end), np.maximum(start, end), np.repeat(np.arange(len(quads)) % 5, 4)]
    assert len(start) > graph.RADIX_FROM
    if shuffled:
        order = np.random.default_rng(8).permutation(len(start))
        keys = [key[order] for key in keys]
    folded = keys[0] * side * side + keys[1]
    assert graph.in_mesh_order(folded, side**4) is not shuffled
    assert np.array_equal(sort_order(*keys), np.lexsort(keys[::-1]))
    assert np.array_equal(sort_order(*keys, stable=False), np.lexsort(keys[::-1]))


def test_radix_order_is_a_stable_argsort():
    rng = np.random.default_rng(9)
    for bits in (1, 16, 17, 40, 62):
        key = rng.integers(0, 2**bits, 200000)
        key[::3] = key[0]                                # ties keep their input order
        assert np.array_equal(graph.radix_order(key, 2**bits), np.argsort(key, kind="stable"))


@pytest.mark.parametrize("sorted_last", [False, True])
def test_row_labels_number_the_distinct_rows_in_sorted_order(sorted_last):
    rng = np.random.default_rng(3)
    rows = rng.integers(0, 10, (500, 3))           # some rows repeat, most neighbours differ in one key only
    if sorted_last:                         # a least significant key already in order: sort_order leaves it out
        rows[:, 2] = np.sort(rows[:, 2])
    labels = graph.row_labels(rows[:, 0], rows[:, 1], rows[:, 2])
    distinct = sorted({tuple(row) for row in rows.tolist()})
    assert labels.tolist() == [distinct.index(tuple(row)) for row in rows.tolist()]
    assert graph.row_labels(np.zeros(0, dtype=np.int64)).shape == (0,)


def test_put_pairs_writes_what_numpy_assignment_writes_repeats_and_rounding_included():
    """Pairs scattered as single 8-byte items equal numpy's row assignment bit for bit: float64 pairs rounded
    to float32, repeated indices (the last pair kept), a (t, 3) index with (t, 3, 2) pairs (a mesh's corners),
    NaN and -0.0; a target that is not C-contiguous (n, 2) float32 is refused."""
    rng = np.random.default_rng(3)
    index = rng.integers(0, 50, (40, 3))                             # repeats certain: 120 writes into 50
    pairs = rng.normal(0, 1, (40, 3, 2)) * 10.0 ** rng.integers(-8, 8, (40, 3, 1))
    pairs[0, 0] = (np.nan, -0.0)
    expected = np.full((50, 2), 7.0, dtype=np.float32)
    expected[index.ravel()] = pairs.reshape(-1, 2)
    target = np.full((50, 2), 7.0, dtype=np.float32)
    graph.put_pairs(target, index, pairs)
    assert np.array_equal(target.view(np.uint32), expected.view(np.uint32))
    for wrong in (np.zeros((50, 2)), np.zeros((50, 3), dtype=np.float32), np.zeros((2, 50), dtype=np.float32).T):
        with pytest.raises(ValueError):
            graph.put_pairs(wrong, index, pairs)
