"""How a chart that folds in projection is cut: every known conflict parted at once, in few pieces.

:func:`.clustering.make_injective` grows a graph Voronoi split from a seed at
each face of a conflicting pair; :func:`split_charts` turns its cells into
connected pieces and merges them back, longest shared boundary first,
wherever no conflicting pair would end up in one piece.  One round parts
every conflict found, so only conflicts along the new cuts need another.
"""

import numpy as np

from ..arrays.graph import connected_components


def part_conflicts(adjacency, edges, on_axis, chart_axis, apart):
    """Split the charts of one axis that hold a conflicting pair so that no pair stays in one chart.

    Parameters
    ----------
    adjacency : Adjacency, of the faces
    edges : (m, 2) int, face adjacency (the same graph)
    on_axis : (f,) int64, chart of each face on this axis (-1: none)
    chart_axis : (c,) int64, signed axis of each chart
    apart : (p, 2) int, face pairs of one chart each (different faces)

    Returns
    -------
    on_axis : (f,) int64, chart_axis : (c + k,) int64, as :func:`split_charts`
    split_faces : (n,) int64, the faces of the charts that were split (all now in new charts)
    """
    sources = np.unique(apart.ravel())
    labels = np.full(len(on_axis), -1, dtype=np.int64)
    labels[sources] = np.arange(len(sources))
    adjacency.grow_labels(labels, lambda s, t: on_axis[s] == on_axis[t])
    split = np.zeros(len(chart_axis), dtype=bool)
    split[on_axis[apart[:, 0]]] = True
    split_faces = np.flatnonzero(split[np.maximum(on_axis, 0)] & (on_axis >= 0))
    on_axis, chart_axis = split_charts(on_axis, labels, chart_axis, edges, split_faces, apart)
    return on_axis, chart_axis, split_faces


def split_charts(on_axis, labels, chart_axis, edges, split_faces, apart):
    """Split some charts of one axis into connected pieces, keeping the faces of each ``apart`` pair apart.

    The pieces start as connected runs of one label (cells of the Voronoi
    split) and are then merged, greedily along the longest shared boundary
    first, wherever no ``apart`` pair would end up in one piece.

    Parameters
    ----------
    on_axis : (f,) int64, chart of each face on this axis (-1: none)
    labels : (f,) int64, the label each face grew (every face of an ``apart`` pair its own)
    chart_axis : (c,) int64, signed axis of each chart
    edges : (m, 2) int, face adjacency
    split_faces : (k,) int, the faces of the charts being split
    apart : (p, 2) int, face pairs that must end in different pieces

    Returns
    -------
    on_axis : (f,) int64, with the split faces in new charts ``c ..`` (the old ids fall out of use)
    chart_axis : (c + p,) int64
    """
    local = np.full(len(on_axis), -1, dtype=np.int64)
    local[split_faces] = np.arange(len(split_faces))
    a, b = local[edges[:, 0]], local[edges[:, 1]]
    inside = (a >= 0) & (b >= 0)
    a, b = a[inside], b[inside]
    faces_a, faces_b = split_faces[a], split_faces[b]
    same_chart = on_axis[faces_a] == on_axis[faces_b]
    same = same_chart & (labels[faces_a] == labels[faces_b])
    cell = connected_components(len(split_faces), np.stack([a[same], b[same]], axis=1))
    # boundaries between cells of one chart, with their length in shared edges
    between = same_chart & ~same
    links, length = np.unique(np.sort(np.stack([cell[a[between]], cell[b[between]]], axis=1), axis=1),
                              axis=0, return_counts=True)
    piece = merge_unless_apart(int(cell.max()) + 1, links[np.lexsort((links[:, 1], links[:, 0], -length))],
                               cell[local[apart]])
    new_on_axis = on_axis.copy()
    new_on_axis[split_faces] = len(chart_axis) + piece[cell]
    first_face = split_faces[np.unique(piece[cell], return_index=True)[1]]
    return new_on_axis, np.concatenate([chart_axis, chart_axis[on_axis[first_face]]])


def merge_unless_apart(count, links, apart):
    """Merge nodes along ``links`` in order, skipping a link that would join two nodes of an ``apart`` pair.

    A Python loop, but over the cells of a split (a few per conflict), never over faces.

    Parameters
    ----------
    count : int
    links : (m, 2) int, node pairs that may merge, in the order to try them
    apart : (p, 2) int, node pairs that must stay in different groups

    Returns
    -------
    (count,) int64, group of each node, numbered ``0 ..`` in the order of their root nodes
    """
    parent = list(range(count))
    enemies = [set() for _ in range(count)]         # kept in terms of roots
    for x, y in apart.tolist():
        enemies[x].add(y)
        enemies[y].add(x)

    def root(x):
        while parent[x] != x:
            parent[x] = parent[parent[x]]
            x = parent[x]
        return x

    for x, y in links.tolist():
        x, y = root(x), root(y)
        if x == y or y in enemies[x]:
            continue
        if len(enemies[x]) > len(enemies[y]):
            x, y = y, x
        parent[x] = y
        for enemy in enemies[x]:
            enemies[enemy].discard(x)
            enemies[enemy].add(y)
        enemies[y] |= enemies[x]
        enemies[x] = set()
    roots = np.array([root(x) for x in range(count)], dtype=np.int64)
    _, group = np.unique(roots, return_inverse=True)
    return group.reshape(-1)
