"""A spike to a stray vertex far out (a scan's outlier, a slip of the mouse) leaves the rest of the bake as it
was: tolerances, welding, chart cuts, the candidate grids and the density all follow the rest of the mesh."""

import warnings

import numpy as np
import pytest

import meshes
from layout_checks import check_texels_finite, overlaps_per_axis
from plane_judge import boxes_within_brute
from seamless_ao.core.mesh.adjacency import face_adjacency
from seamless_ao.core.charts.candidates import candidate_pairs, without_quiet_sides
from seamless_ao.core.charts.clustering import cut_long_charts, signed_axis_clusters
from seamless_ao.core.layout import build_layout
from seamless_ao.core.mesh.triangle_mesh import TriangleMesh
from seamless_ao.core.mesh.weld import weld_vertices
from seamless_ao.core.rays.ray_setup import ray_part, world_reach
from seamless_ao.core.settings import BakeSettings


def with_spike(positions, triangles, far, base=None):
    """The mesh plus one triangle from its first triangle's first side (or from its first vertex and a new
    vertex ``base`` away) to a new vertex ``far`` out along x."""
    positions = np.asarray(positions, dtype=np.float64)
    first, second = triangles[0, 0], triangles[0, 1]
    if base is not None:
        positions = np.vstack([positions, positions[first] + [0.0, 0.0, base]])
        second = len(positions) - 1
    positions = np.vstack([positions, [[far, 0.0, 0.0]]])
    return positions, np.vstack([triangles, [[first, second, len(positions) - 1]]])


@pytest.fixture(scope="module")
def scan():
    from real_assets import noisy_scan
    return noisy_scan(triangles=20_000)


@pytest.mark.parametrize("far", [1e4, 1e12])
def test_a_spike_to_a_stray_vertex_leaves_the_rest_of_the_layout_as_it_was(scan, far):
    """Before, a spike 1e4 out welded 485 of the scan's vertices together and its charts folded; at 1e12
    cutting its chart into slabs asked for terabytes.  Now the tolerances are those of the scan alone, the
    spike's chart alone is packed at a lower density (and the bake says so), and the layout is fold-free."""
    plain = TriangleMesh.from_triangles(*scan, smooth=True)
    spiked = TriangleMesh.from_triangles(*with_spike(*scan, far), smooth=True)
    assert spiked.scale == plain.scale
    assert face_adjacency(spiked).welded_triangles.max() == face_adjacency(plain).welded_triangles.max() + 1
    before, after = build_layout(plain, image_size=256), build_layout(spiked, image_size=256)
    assert after.atlas.utilisation > 0.8 * before.atlas.utilisation
    assert after.atlas.density > 0.8 * before.atlas.density
    assert not before.atlas.warnings
    assert [w for w in after.atlas.warnings if "1 chart was too long for the image" in w]
    check_texels_finite(after)
    assert overlaps_per_axis(spiked, face_adjacency(after.mesh), after.charts) == [0, 0, 0]


def debris(positions, triangles, kind, rng):
    """``positions, triangles`` plus debris far out: three spikes in three directions, three floating
    clusters of five triangles, or a sheet of seven triangles fanning out from one vertex to 10^7."""
    positions, triangles = np.asarray(positions, dtype=np.float64), np.asarray(triangles)
    if kind == "spikes":
        for far, direction in ((1e3, (1.0, 0.2, 0.0)), (1e8, (0.0, -1.0, 0.3)), (1e11, (-0.6, 0.6, 0.5))):
            first, second = triangles[rng.integers(len(triangles)), :2]
            positions = np.vstack([positions, np.array(direction) * far])
            triangles = np.vstack([triangles, [[first, second, len(positions) - 1]]])
    elif kind == "floaters":
        for far, direction in ((1e2, (1.0, 1.0, 0.0)), (1e5, (0.0, -1.0, 0.0)), (1e9, (0.0, 0.0, 1.0))):
            corners = np.array(direction) * far + rng.normal(0.0, 0.5, (15, 3))
            triangles = np.vstack([triangles, len(positions) + np.arange(15).reshape(5, 3)])
            positions = np.vstack([positions, corners])
    else:
        ends = 1e7 * np.stack([np.ones(8), np.linspace(-1e-3, 1e-3, 8), np.zeros(8)], axis=1)
        start = len(positions)
        positions = np.vstack([positions, ends])
        triangles = np.vstack([triangles, np.stack([np.full(7, triangles[0, 0]), start + np.arange(7),
                                                    start + 1 + np.arange(7)], axis=1)])
    return positions, triangles


@pytest.mark.parametrize("kind", ["spikes", "floaters", "sheet"])
@pytest.mark.parametrize("image_size", [256, 1024])
def test_debris_far_out_leaves_the_rest_of_the_layout_as_it_was(kind, image_size):
    """Each of these once left the sphere a few texels, or welded it into a handful of vertices: three
    spikes outran the one vertex the box left out at each end, three floating clusters the allowance of
    stray triangles, and a sheet of spikes 10^7 out is more surface than the sphere.  What the mesh's size
    leaves out is debris: its charts get few texels, and the sphere keeps its own."""
    sphere = meshes.uv_sphere(rings=30, segments=60)
    plain = TriangleMesh.from_triangles(*sphere, smooth=True)
    mesh = TriangleMesh.from_triangles(*debris(*sphere, kind, np.random.default_rng(0)), smooth=True)
    assert mesh.scale == plain.scale and mesh.stray.sum() == len(mesh.triangles) - len(plain.triangles)
    before, after = build_layout(plain, image_size=image_size), build_layout(mesh, image_size=image_size)
    assert after.atlas.utilisation > 0.8 * before.atlas.utilisation
    check_texels_finite(after)
    assert overlaps_per_axis(mesh, face_adjacency(after.mesh), after.charts) == [0, 0, 0]


def test_a_spike_at_a_given_texel_density_is_shrunk_instead_of_refused():
    """With a texel density instead of an image size, a face that would need an image wider than the
    largest allowed is packed at a lower density of its own; it used to refuse the whole bake."""
    sphere = meshes.uv_sphere(rings=30, segments=60)
    mesh = TriangleMesh.from_triangles(*with_spike(*sphere, 1e6, base=0.01), smooth=True)
    layout = build_layout(mesh, density=40.0)
    assert max(layout.atlas.width, layout.atlas.height) <= 4096 + 16
    assert [w for w in layout.atlas.warnings if "too long for the image" in w]
    check_texels_finite(layout)


def test_the_box_of_a_mesh_leaves_out_a_spike_but_not_a_long_tip_or_loose_vertices():
    from seamless_ao.core.mesh.extent import robust_box
    sphere_positions, sphere_triangles = meshes.uv_sphere(rings=30, segments=60)
    full = (sphere_positions.min(axis=0), sphere_positions.max(axis=0))
    positions, triangles = with_spike(sphere_positions, sphere_triangles, 1e5)
    low, high, stray = robust_box(positions, triangles)
    assert np.array_equal(np.array([low, high]), np.array(full)) and np.flatnonzero(stray).tolist() == [len(triangles) - 1]
    # a stray vertex in no triangle never counts
    loose = np.vstack([sphere_positions, [[1e9, 0.0, 0.0]]])
    assert np.array_equal(np.array(robust_box(loose, sphere_triangles)[:2]), np.array(full))
    # under 1,000 triangles nothing is left out
    small_positions, small_triangles = meshes.uv_sphere(rings=10, segments=20)
    positions, triangles = with_spike(small_positions, small_triangles, 1e5)
    assert robust_box(positions, triangles)[1][0] == 1e5
    # a cone 20 times longer than wide: one vertex far out, but half the triangles reach it
    segments = 700
    angle = np.linspace(0.0, 2 * np.pi, segments, endpoint=False)
    ring = np.stack([np.cos(angle), np.sin(angle), np.zeros(segments)], axis=1) * 0.5
    positions = np.vstack([ring, [[0.0, 0.0, 20.0]], [[0.0, 0.0, 0.0]]])
    following = np.roll(np.arange(segments), -1)
    triangles = np.concatenate([np.stack([np.arange(segments), following, np.full(segments, segments)], 1),
                                np.stack([following, np.arange(segments), np.full(segments, segments + 1)], 1)])
    low, high, stray = robust_box(positions, triangles)
    assert not stray.any()
    assert high[2] == 20.0 and len(triangles) >= 1000


def test_welding_vertices_far_out_neither_overflows_nor_welds_distinct_ones():
    rng = np.random.default_rng(0)
    positions = np.vstack([rng.random((200, 3)), [[1e20, 0.0, 0.0], [1e20, 1e12, 0.0], [1e20, 0.0, 0.0]]])
    positions[1] = positions[0] + 1e-9
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        welded = weld_vertices(positions, 1e-6)
    assert welded[1] == welded[0]
    assert welded[200] == welded[202] != welded[201]
    assert len(np.unique(welded)) == 201


def test_a_chart_with_a_face_far_out_is_cut_only_where_it_has_faces():
    """A strip of 600 unit quads and one spike 1e12 out, in one chart: cutting it every 100 units made
    1e10 slabs (and asked for 80 GB); only the slabs with faces in them become charts."""
    triangles = meshes.grid_triangles(2, 601)
    positions = np.array([[float(i % 601), float(i // 601), 0.0] for i in range(1202)] + [[1e12, 0.5, 0.0]])
    triangles = np.vstack([triangles, [[600, 1202, 1201]]])                    # on the strip's end, facing +z
    mesh = TriangleMesh.from_triangles(positions, triangles)
    charts = signed_axis_clusters(mesh, face_adjacency(mesh))
    assert charts.count == 1
    cut = cut_long_charts(mesh, charts, 100.0)
    assert 7 <= cut.count <= 8
    column = cut.chart_of_face[:, 2]
    strip_faces = np.arange(len(triangles) - 1)
    for chart in np.unique(column[strip_faces]):
        x = positions[triangles[strip_faces[column[strip_faces] == chart]]][..., 0]
        assert x.max() - x.min() <= 101.0


def spiked_shapes(rng, count, far, corners):
    """Shapes of mixed sizes in groups -1..3, and giants: a corner of some pulled ``far`` out along a few
    directions; two of group 5 overlap only far out, group 6 has one giant alone."""
    start = rng.uniform(0, 20, (count, 1, 2))
    size = np.where(rng.random(count) < 0.05, rng.uniform(3, 12, count), rng.exponential(0.4, count))
    shapes = start + rng.normal(0, 1, (count, corners, 2)) * size[:, None, None]
    group = rng.integers(-1, 4, count)
    directions = np.array([[1.0, 0.0], [0.0, -1.0], [-0.7, 0.7], [1.0, 1.0]])
    spikes = rng.choice(count, 16, replace=False)
    shapes[spikes, -1] = far * directions[rng.integers(0, 4, 16)]
    group[spikes[:2]] = 5
    shapes[spikes[1], -1] = shapes[spikes[0], -1] + 0.5
    group[spikes[2]] = 6
    return shapes, group


@pytest.mark.parametrize("seed, far, margin", [(0, 1e6, 0.0), (1, 1e15, 0.3), (2, 1e6, 1.0), (3, 1e15, 0.0)])
def test_candidate_pairs_with_spikes_far_out_are_the_brute_force_pairs(seed, far, margin):
    rng = np.random.default_rng(seed)
    for corners in (2, 3):
        shapes, group = spiked_shapes(rng, 500, far, corners)
        expected = boxes_within_brute(shapes, group, margin)
        assert len(expected) > 100 and [5, 5] in group[expected].tolist()
        assert np.array_equal(candidate_pairs(shapes, group, margin), expected)
        query = rng.random(len(shapes)) < 0.2
        asked = candidate_pairs(shapes, group, margin, query=query)
        assert np.array_equal(asked, expected[query[expected[:, 0]] | query[expected[:, 1]]])
        depth = rng.normal(0, 1.5, (len(shapes), 1)) + rng.exponential(0.3, (len(shapes), corners))
        a, b = expected[:, 0], expected[:, 1]
        deep = expected[np.maximum(depth[a].max(1) - depth[b].min(1), depth[b].max(1) - depth[a].min(1)) > 0.8]
        assert np.array_equal(candidate_pairs(shapes, group, margin, depth=depth, spread=0.8), deep)


def test_without_quiet_sides_keeps_both_sides_of_a_deep_pair_with_a_spike_far_out():
    """The segments of a gentle slope, two spikes far out whose ends meet there, and one spike passing
    close above a short segment at a depth far from it: every pair within the margin and spread more than it
    in depth keeps both sides (checked against every pair)."""
    rng = np.random.default_rng(4)
    start = rng.uniform(0, 10, (400, 2))
    seg = np.stack([start, start + rng.normal(0, 0.2, (400, 2))], axis=1)
    seg_depth = 0.05 * start[:, :1] + [0.0, 0.01]
    seg[:2, 1] = [1e12, 5.0]
    seg[1, 0] = [3.0, 3.0]
    seg_depth[:2] = [[0.0, 0.0], [0.0, 2.0]]
    seg[2] = [[-1e12, 5.1], [9.0, 5.1]]
    seg[3] = [[4.0, 5.0], [4.2, 5.0]]
    seg_depth[2], seg_depth[3] = [0.2, 0.2], [0.9, 0.9]
    seg_group = np.zeros(400, dtype=np.int64)
    margin = 0.25
    loud = without_quiet_sides(seg, seg_depth, seg_group, margin)
    low, high = seg.min(axis=1), seg.max(axis=1)
    a, b = np.triu_indices(400, 1)
    gap = np.maximum(low[a] - high[b], low[b] - high[a]).max(axis=1)
    spread = np.maximum(seg_depth[a].max(axis=1) - seg_depth[b].min(axis=1),
                        seg_depth[b].max(axis=1) - seg_depth[a].min(axis=1))
    must = (gap <= margin) & (spread > margin)
    assert must[(a == 0) & (b == 1)].any() and must[(a == 2) & (b == 3)].any()
    assert (loud[a[must]] >= 0).all() and (loud[b[must]] >= 0).all()
    assert (loud == -1).sum() > 200                                  # and it still leaves most sides out


def test_a_small_mesh_whose_faces_vanish_next_to_vertices_far_out_is_refused_saying_why():
    """Under 1,000 triangles nothing is left out of the mesh's size, so a small triangle 10^12 out makes
    every face zero-area next to it.  The refusal says that, rather than that the faces have no area."""
    from seamless_ao.core.errors import SeamlessAOError
    from seamless_ao.core.mesh.triangle_mesh import require_faces
    positions, triangles = meshes.uv_sphere(rings=10, segments=20)
    positions = np.vstack([positions, [[1e12, 0.0, 0.0], [1e12, 1.0, 0.0], [1e12, 0.0, 1.0]]])
    triangles = np.vstack([triangles, [[len(positions) - 3, len(positions) - 2, len(positions) - 1]]])
    with pytest.raises(SeamlessAOError, match="too small to bake next to its size .* far from the rest"):
        require_faces(TriangleMesh.from_triangles(positions, triangles))
    with pytest.raises(SeamlessAOError, match="zero area"):
        require_faces(TriangleMesh.from_triangles(np.zeros((3, 3)), [[0, 1, 2]]))


@pytest.mark.parametrize("far", [-1e3, 1e8])
def test_a_spike_neither_lengthens_the_rays_nor_drops_the_ground_plane(scan, far):
    """The automatic maximum distance is half the mesh's size and the ground plane lies at its lowest
    point: a spike to a stray vertex (here below the scan too, rotated in the world) changes neither, nor
    the box the scene's occluders are gathered around; before, the rays of the scan reached as far as the
    spike and the ground dropped to its tip."""
    positions, triangles = scan
    spiked = with_spike(positions, triangles, 1.0, base=0.1)[0]
    spiked[-1] = [far, far, far]
    alone = TriangleMesh.from_triangles(positions, triangles)
    with_it = TriangleMesh.from_triangles(spiked, with_spike(positions, triangles, 1.0, base=0.1)[1])
    assert with_it.stray.sum() == 1
    matrix = np.eye(4)
    matrix[:3, :3] = [[0.0, -2.0, 0.0], [2.0, 0.0, 0.0], [0.0, 0.0, 2.0]]
    matrix[:3, 3] = [5.0, -3.0, 1.0]
    settings = BakeSettings(use_ground_plane=True, use_scene_occluders=True)
    parts = [ray_part(mesh, matrix, settings, lambda *arrays: None) for mesh in (alone, with_it)]
    expected, found = parts[0].params, parts[1].params
    assert found.max_distance == pytest.approx(expected.max_distance, rel=1e-9)
    assert found.ground_height == pytest.approx(expected.ground_height, abs=1e-9 * alone.scale)
    assert found.offset == pytest.approx(expected.offset, rel=1e-9)
    for one, other in zip(world_reach(alone, matrix, settings), world_reach(with_it, matrix, settings)):
        assert np.allclose(one, other, rtol=1e-9, atol=1e-9)
