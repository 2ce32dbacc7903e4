"""A coarse stand-in for a mesh far finer than its image: its vertices clustered in cubes about a texel wide.

Issue 56 asks for a layout whose cost follows the image, not the triangles:
on a million-triangle sculpt baked at 256², some twenty triangles share a
texel, and the charts, the fold tests and the packing decide things no texel
can show.  This module makes the stand-in (a proxy) those steps could run on:

    cluster_of_vertex, cluster_position = grid_clusters(positions, cell)
    proxy, proxy_of_triangle = proxy_triangles(cluster_of_vertex, triangles)

The layout's charts are made on it where a mesh has several triangles a
texel (:mod:`..charts.coarse`, which says what becomes of the guarantees).
``tests/bench/bench_texel_proxy.py`` measures what the layout costs on such a
proxy against the whole mesh.
"""

import numpy as np

from ..arrays.graph import row_labels
from ..arrays.reduce import column_min, row_all

#: Cube indices are clipped to this many cubes from the mesh's lowest corner: a stray vertex 10^18 out at a
#: cell of 10^-3 would otherwise overflow int64 (far vertices then share the last cube; they are strays).
FARTHEST_CUBE = 2**40


def grid_clusters(positions, cell, groups=None):
    """Cluster of every vertex: the vertices in one cube of side ``cell`` (and of one group) share one.

    Parameters
    ----------
    positions : (v, 3) float, object units
    cell : float > 0, object units
    groups : (v,) int >= 0, optional: vertices of different groups (the parts of a combined mesh) never share a
        cluster

    Returns
    -------
    cluster_of_vertex : (v,) int64
        Numbered ``0 .. c-1`` in the order of the cubes (group, then x, y, z).
    cluster_position : (c, 3) float64
        The mean position of each cluster's vertices.
    """
    positions = np.asarray(positions, dtype=np.float64).reshape(-1, 3)
    if not cell > 0.0:
        raise ValueError("cell must be positive, got {!r}".format(cell))
    if not len(positions):
        return np.zeros(0, dtype=np.int64), np.zeros((0, 3))
    finite = row_all(np.isfinite(positions))
    low = column_min(positions[finite]) if finite.any() else np.zeros(3)
    cube = np.floor((np.where(finite[:, None], positions, low) - low) / cell)
    cube = np.clip(cube, 0.0, float(FARTHEST_CUBE)).astype(np.int64)
    keys = [cube[:, 0], cube[:, 1], cube[:, 2]]
    if groups is not None:
        keys.insert(0, np.asarray(groups, dtype=np.int64))
    cluster_of_vertex = row_labels(*keys)
    count = int(cluster_of_vertex.max()) + 1
    # a non-finite vertex sits in the lowest corner's cube and adds nothing to its cluster's mean
    finite_count = np.bincount(cluster_of_vertex, weights=finite.astype(np.float64), minlength=count)
    sums = np.stack([np.bincount(cluster_of_vertex, weights=np.where(finite, positions[:, k], 0.0), minlength=count)
                     for k in range(3)], axis=1)
    cluster_position = np.where(finite_count[:, None] > 0, sums / np.maximum(finite_count, 1.0)[:, None], low)
    return cluster_of_vertex, cluster_position


def proxy_triangles(cluster_of_vertex, triangles):
    """The triangles of the clusters: each triangle whose corners fall in three clusters becomes one, once per
    set of clusters and winding (the two sides of a sheet thinner than a cube stay two triangles).

    Parameters
    ----------
    cluster_of_vertex : (v,) int, as :func:`grid_clusters` gives it
    triangles : (t, 3) int, vertex indices

    Returns
    -------
    proxy : (p, 3) int64
        Cluster indices of each proxy triangle, its smallest first, the winding kept; sorted.
    proxy_of_triangle : (t,) int64
        The proxy triangle of each triangle; -1 where two of its corners share a cluster.
    """
    triangles = np.asarray(triangles, dtype=np.int64).reshape(-1, 3)
    corner_cluster = np.asarray(cluster_of_vertex, dtype=np.int64)[triangles]
    a, b, c = corner_cluster.T
    three = (a != b) & (b != c) & (a != c)
    proxy_of_triangle = np.full(len(triangles), -1, dtype=np.int64)
    kept = corner_cluster[three]
    if not len(kept):
        return np.zeros((0, 3), dtype=np.int64), proxy_of_triangle
    # a cyclic turn keeps the winding: (a, b, c), (b, c, a) and (c, a, b) are one triangle
    first = np.argmin(kept, axis=1)
    kept = np.take_along_axis(kept, (first[:, None] + np.arange(3)) % 3, axis=1)
    number = row_labels(kept[:, 0], kept[:, 1], kept[:, 2])
    proxy = np.empty((int(number.max()) + 1, 3), dtype=np.int64)
    proxy[number] = kept
    proxy_of_triangle[three] = number
    return proxy, proxy_of_triangle
