"""core/mesh/proxy.py: a mesh's vertices clustered in cubes, and the triangles of those clusters."""

import numpy as np
import pytest

from seamless_ao.core.mesh.proxy import grid_clusters, proxy_triangles


def _cube_of(positions, cell):
    """Brute force: each vertex's cube, counted from the lowest corner, as a tuple."""
    low = positions.min(axis=0)
    return [tuple(int(v) for v in np.floor((point - low) / cell)) for point in positions]


@pytest.mark.parametrize("seed", [0, 1])
def test_vertices_share_a_cluster_exactly_when_they_share_a_cube(seed):
    rng = np.random.default_rng(seed)
    positions = rng.uniform(-1.0, 2.0, (400, 3))
    positions[:60:2] = positions[1:60:2]                              # some repeated vertices
    cell = 0.37
    cluster, centre = grid_clusters(positions, cell)
    cubes = _cube_of(positions, cell)
    for i in range(0, len(positions), 3):
        for j in range(i + 1, len(positions), 5):
            assert (cluster[i] == cluster[j]) == (cubes[i] == cubes[j])
    assert sorted(set(cluster.tolist())) == list(range(len(set(cubes))))
    for k in range(len(centre)):
        assert np.allclose(centre[k], positions[cluster == k].mean(axis=0), rtol=0.0, atol=1e-12)


def test_groups_never_share_a_cluster():
    positions = np.array([[0.0, 0.0, 0.0], [0.01, 0.0, 0.0], [0.02, 0.0, 0.0], [0.03, 0.0, 0.0]])
    cluster, _ = grid_clusters(positions, 1.0, groups=np.array([0, 1, 0, 1]))
    assert cluster[0] == cluster[2] and cluster[1] == cluster[3] and cluster[0] != cluster[1]


def test_strays_and_non_finite_vertices_stay_finite():
    positions = np.array([[0.0, 0.0, 0.0], [0.1, 0.0, 0.0], [1e18, 1e18, 1e18], [np.nan, 0.0, 0.0],
                          [np.inf, 1.0, 1.0], [2e18, 0.0, 0.0]])
    cluster, centre = grid_clusters(positions, 1e-3)
    assert np.isfinite(centre).all()
    assert len(set(cluster[:2].tolist())) == 2                       # a millimetre cube each
    assert cluster[3] == cluster[4] == cluster[0]                     # non-finite: the lowest corner's cube
    assert np.allclose(centre[cluster[0]], [0.0, 0.0, 0.0])           # and they add nothing to its mean
    with pytest.raises(ValueError):
        grid_clusters(positions, 0.0)


def _grid_sheet(n, spacing=1.0):
    """A flat n x n quad grid in the z = 0 plane, two triangles a quad, counter-clockwise seen from +z."""
    x, y = np.meshgrid(np.arange(n + 1) * spacing, np.arange(n + 1) * spacing, indexing="ij")
    positions = np.stack([x.ravel(), y.ravel(), np.zeros(x.size)], axis=1)
    index = np.arange((n + 1) ** 2).reshape(n + 1, n + 1)
    a, b, c, d = index[:-1, :-1].ravel(), index[1:, :-1].ravel(), index[1:, 1:].ravel(), index[:-1, 1:].ravel()
    return positions, np.concatenate([np.stack([a, b, c], 1), np.stack([a, c, d], 1)])


def _normals(positions, triangles):
    p = positions[triangles]
    return np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])


def test_proxy_triangles_keep_the_winding_and_map_every_triangle_of_three_clusters():
    positions, triangles = _grid_sheet(24)
    positions = positions + 0.013                                     # no vertex on a cube's face
    cluster, centre = grid_clusters(positions, 3.3)
    proxy, proxy_of_triangle = proxy_triangles(cluster, triangles)
    corner_cluster = cluster[triangles]
    three = np.array([len(set(row)) == 3 for row in corner_cluster.tolist()])
    assert np.array_equal(proxy_of_triangle >= 0, three) and three.any() and (~three).any()
    # each mapped triangle's clusters are its proxy triangle's, turned, not mirrored
    for t in np.flatnonzero(three):
        row, target = corner_cluster[t].tolist(), proxy[proxy_of_triangle[t]].tolist()
        assert target in (row, row[1:] + row[:1], row[2:] + row[:2])
    assert (proxy[:, 0] < proxy[:, 1:].min(axis=1)).all()
    assert len({tuple(row) for row in proxy.tolist()}) == len(proxy)   # each once
    assert set(proxy_of_triangle[three].tolist()) == set(range(len(proxy)))
    assert (_normals(centre, proxy)[:, 2] > 0.0).all()                  # facing +z, as the sheet


def test_the_two_sides_of_a_thin_sheet_stay_two_proxy_triangles():
    positions, triangles = _grid_sheet(12)
    positions = positions + 0.013
    back = positions + [0.0, 0.0, 0.01]                               # the other side, a hundredth away
    both = np.concatenate([positions, back])
    flipped = triangles[:, ::-1] + len(positions)
    cluster, centre = grid_clusters(both, 2.7)
    proxy, proxy_of_triangle = proxy_triangles(cluster, np.concatenate([triangles, flipped]))
    front_proxy, back_proxy = proxy_of_triangle[:len(triangles)], proxy_of_triangle[len(triangles):]
    mapped = front_proxy >= 0
    assert np.array_equal(mapped, back_proxy >= 0) and mapped.any()
    assert not set(front_proxy[mapped].tolist()) & set(back_proxy[mapped].tolist())
    assert (_normals(centre, proxy[front_proxy[mapped]])[:, 2] > 0).all()
    assert (_normals(centre, proxy[back_proxy[mapped]])[:, 2] < 0).all()


def test_a_turned_triangle_is_the_same_proxy_triangle():
    cluster = np.arange(6)
    triangles = np.array([[0, 1, 2], [1, 2, 0], [2, 0, 1], [0, 2, 1], [3, 4, 5], [3, 3, 4]])
    proxy, proxy_of_triangle = proxy_triangles(cluster, triangles)
    assert proxy.tolist() == [[0, 1, 2], [0, 2, 1], [3, 4, 5]]
    assert proxy_of_triangle.tolist() == [0, 0, 0, 1, 2, -1]


def test_nothing_in_nothing_out():
    cluster, centre = grid_clusters(np.zeros((0, 3)), 1.0)
    assert cluster.shape == (0,) and centre.shape == (0, 3)
    proxy, proxy_of_triangle = proxy_triangles(np.zeros(3, dtype=np.int64), np.array([[0, 1, 2]]))
    assert proxy.shape == (0, 3) and proxy_of_triangle.tolist() == [-1]
