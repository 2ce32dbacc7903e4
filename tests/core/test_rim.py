"""Issue 56: the rim of an atlas' members from the mesh's pairs of sides, the same as the rule on every member's
sides (core/atlas/rim.py)."""

import numpy as np
import pytest

import meshes
from seamless_ao.core.atlas import raster
from seamless_ao.core.atlas.rim import ALONE, SHARED, edge_twins, member_rim, rim_triangles, side_twins
from seamless_ao.core.layout import build_layout
from seamless_ao.core.mesh.triangle_mesh import TriangleMesh


def twins_by_definition(triangles):
    """side_twins side by side: the other sides on the same two vertices, and which way each runs."""
    sides = {}
    for index, (a, b) in enumerate(zip(triangles.ravel(), np.roll(triangles, -1, axis=1).ravel())):
        sides.setdefault((min(a, b), max(a, b)), []).append((index, a < b))
    expected = np.full(triangles.size, ALONE)
    for index, (a, b) in enumerate(zip(triangles.ravel(), np.roll(triangles, -1, axis=1).ravel())):
        others = [(other, forward) for other, forward in sides[min(a, b), max(a, b)] if other != index]
        if a == b or not others:
            continue
        if len(others) > 1:
            expected[index] = SHARED
        elif others[0][1] != (a < b):
            expected[index] = others[0][0]
    return expected.reshape(-1, 3)


def edges_by_vertex_pair(triangles):
    """A number for every side, shared exactly by the sides on the same two vertices (as Blender's edges)."""
    ends = np.stack([triangles.ravel(), np.roll(triangles, -1, axis=1).ravel()], axis=1)
    return np.unique(np.sort(ends, axis=1), axis=0, return_inverse=True)[1].reshape(-1, 3)


@pytest.mark.parametrize("seed", range(4))
def test_side_twins_and_edge_twins_pair_each_side_with_the_one_other_on_its_vertices_the_other_way(seed):
    """Triangles drawn from a few vertices make shared, folded, tripled and pointless sides (a vertex joined to
    itself); a torus, none of those."""
    rng = np.random.default_rng(seed)
    triangles = rng.integers(0, 12, (50, 3)) if seed else meshes.torus(rings=8, segments=6)[1]
    expected = twins_by_definition(triangles)
    assert np.array_equal(side_twins(triangles), expected)
    if seed:
        assert {ALONE, SHARED} <= set(expected.ravel()) and (expected >= 0).any()
        keep = (triangles != np.roll(triangles, -1, axis=1)).all(axis=1)     # a Blender edge joins two vertices
        triangles, expected = triangles[keep], twins_by_definition(triangles[keep])
    assert np.array_equal(edge_twins(edges_by_vertex_pair(triangles), triangles), expected)
    assert side_twins(triangles[:0]).shape == edge_twins(np.zeros((0, 3), dtype=int), triangles[:0]).shape == (0, 3)
    # numbers that pair sides on different vertices (a mesh whose corners' edges are wrong): the vertices decide
    wrong = np.arange(triangles.size).reshape(-1, 3) // 2
    assert np.array_equal(edge_twins(wrong, triangles), expected)


def with_fins_and_copies(positions, triangles, count, seed):
    """The mesh with ``count`` triangles copied and ``count`` fins (a triangle on one of its sides, out of
    its plane): non-manifold edges, where the rule decides among three sides or more."""
    rng = np.random.default_rng(seed)
    picked = rng.choice(len(triangles), 2 * count, replace=False)
    copies = triangles[picked[:count]]
    fin_side = triangles[picked[count:]][:, :2]
    tips = positions[fin_side].mean(axis=1) + 0.05 * rng.normal(size=(count, 3))
    fins = np.column_stack([fin_side[:, 1], fin_side[:, 0], len(positions) + np.arange(count)])
    return np.concatenate([positions, tips]), np.concatenate([triangles, copies, fins])


@pytest.mark.parametrize("shape", ["torus", "box", "fins"])
def test_the_rim_of_an_atlas_members_from_the_meshes_twins_is_the_rule_on_all_their_sides(shape):
    """A layout's live members, a corner being one vertex in one chart: member_rim through side_twins and
    through edge numbers gives what rim_triangles gives on every member's corners (a curved surface's charts
    overlap, so a triangle is a member of several)."""
    if shape == "torus":
        positions, triangles = meshes.torus(rings=24, segments=12)
    elif shape == "box":
        positions, triangles = meshes.box(subdivisions=6)
    else:
        positions, triangles = with_fins_and_copies(*meshes.torus(rings=24, segments=12), count=12, seed=1)
    mesh = TriangleMesh.from_triangles(positions, triangles)
    atlas = build_layout(mesh, image_size=128).atlas
    live = np.flatnonzero(atlas.member_placed & ~mesh.degenerate[atlas.member_triangle])
    expected = rim_triangles(atlas.member_chart[live, None] * np.int64(len(mesh.positions))
                             + mesh.triangles[atlas.member_triangle[live]])
    assert 0 < expected.sum() < len(live)                                    # inner members and rim members
    assert (len(live) > len(triangles)) == (shape != "box")           # a box's flat sides' charts do not overlap
    for twin in (side_twins(mesh.triangles), edge_twins(edges_by_vertex_pair(mesh.triangles), mesh.triangles)):
        assert (twin == SHARED).any() == (shape == "fins")
        found = member_rim(twin, mesh.triangles, atlas.member_triangle, atlas.member_chart, atlas.charts.chart_axis,
                           atlas.membership, live)
        assert np.array_equal(found, expected)
    # and the rasteriser's, with the mesh's edge numbers and without
    assert np.array_equal(raster._live_rim(atlas, mesh, live), expected)
    mesh.side_edge = edges_by_vertex_pair(mesh.triangles)
    assert np.array_equal(raster._live_rim(atlas, mesh, live), expected)


def test_meshes_put_together_number_their_side_edges_apart():
    """Each mesh's edge numbers after the last one's, so sides of different meshes never pair (nor do their
    vertices); none unless every mesh has them; a side numbered below zero, or a number missing, is refused."""
    positions, triangles = meshes.torus(rings=8, segments=6)
    given = TriangleMesh(positions, triangles, np.arange(len(triangles)), np.ones((len(triangles), 3, 3)),
                         side_edge=edges_by_vertex_pair(triangles))
    together, _ = TriangleMesh.concatenate([given, given])
    assert np.array_equal(edge_twins(together.side_edge, together.triangles), side_twins(together.triangles))
    assert TriangleMesh.concatenate([given, TriangleMesh.from_triangles(positions, triangles)])[0].side_edge is None
    for wrong in (given.side_edge[1:], given.side_edge - 1):
        with pytest.raises(ValueError, match="edge number"):
            TriangleMesh(positions, triangles, given.triangle_face, given.normals_as_read, side_edge=wrong)
