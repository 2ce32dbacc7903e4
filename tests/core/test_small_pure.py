"""The small pure functions moved out of the Blender side (issue 15): PNG encoding, vertex averaging,
the memory estimate, a bake's ray parameters, the one adaptive stop, export settings."""


import numpy as np
import pytest

from seamless_ao.core.rays.ao import settle_pilot
from seamless_ao.core.budget import check_budget, estimated_bytes, planned_size
from seamless_ao.core.errors import SeamlessAOError
from seamless_ao.core.export.transfer import sample_repeat, texel_uv, vertex_average
from seamless_ao.core.arrays import blocks
from seamless_ao.core.arrays.graph import Adjacency, sort_order
from seamless_ao.core.mesh.triangle_mesh import duplicate_triangle_count, sanitized_normals
from seamless_ao.core.mesh.weld import weld_vertices
from seamless_ao.core.charts.candidates import candidate_pairs, without_flat_groups, without_quiet_sides
from seamless_ao.core.arrays.geometry2d import segment_distance, triangle_angles
from seamless_ao.core.atlas.packing import SMALL_TEXELS, density_filling
from seamless_ao.core.export.png import encode_png
from seamless_ao.core.rays.ray_setup import AOParams, ao_params
from seamless_ao.core.settings import BakeSettings, ExportSettings

from png_levels import decode_png


@pytest.mark.parametrize("bit_depth", [8, 16])
@pytest.mark.parametrize("channels", [1, 2, 3, 4])
def test_encode_png_round_trips_every_depth_and_channel_count(bit_depth, channels):
    values = np.random.default_rng(channels).random((5, 7, channels))
    values[0, 0, 0], values[4, 6, -1] = -0.5, 1.5                        # clipped
    decoded, depth = decode_png(encode_png(values if channels > 1 else values[:, :, 0], bit_depth))
    expected = np.round(np.clip(values, 0.0, 1.0) * (2 ** bit_depth - 1))
    assert depth == bit_depth and decoded.shape == (5, 7, channels) and np.array_equal(decoded, expected)


def test_encode_png_refuses_what_no_png_can_hold():
    for values, depth in ((np.full((2, 2), np.nan), 8), (np.zeros((2, 2, 5)), 8), (np.zeros((0, 3)), 8),
                          (np.zeros((2, 2)), 12)):
        with pytest.raises(ValueError):
            encode_png(values, depth)


def test_vertex_average_means_corners_and_leaves_unused_vertices_open():
    corner_values = np.array([0.2, 0.4, 0.9, 0.0])
    corner_vertex = np.array([0, 0, 2, 2])
    assert np.allclose(vertex_average(corner_values, corner_vertex, 4), [0.3, 1.0, 0.45, 1.0])


def test_memory_estimate_grows_with_texels_and_pixels_and_is_refused_over_the_budget():
    settings = BakeSettings(quality="CUSTOM", image_size=1024)
    pixels, texels = planned_size(settings, surface_area=123.0)
    assert pixels == 1024**2 and texels < pixels                      # the image size, whatever the area
    dense = BakeSettings(quality="CUSTOM", size_mode="DENSITY", texel_density=100.0)
    assert planned_size(dense, 2.0)[0] == pytest.approx(2 * planned_size(dense, 1.0)[0])
    assert estimated_bytes(1000, 2 * texels, pixels) > estimated_bytes(1000, texels, pixels)
    assert estimated_bytes(2000, texels, pixels) > estimated_bytes(1000, texels, pixels)
    assert estimated_bytes(1000, texels, pixels, cycles=True) > estimated_bytes(1000, texels, pixels) + 100 * 2**20
    check_budget(settings, 1000, pixels, texels)
    with pytest.raises(SeamlessAOError, match="memory budget of 64 MB"):
        check_budget(BakeSettings(memory_budget_mb=64), 1000, pixels, texels)
    # the Cycles caster's own memory counts where the settings take it (Automatic at the defaults)
    nodes_only = estimated_bytes(1000, texels, pixels) / 2**20
    budget = int(nodes_only) + 50
    check_budget(BakeSettings(memory_budget_mb=budget, ray_caster="GEOMETRY_NODES"), 1000, pixels, texels)
    with pytest.raises(SeamlessAOError, match="memory budget of {:,} MB".format(budget)):
        check_budget(BakeSettings(memory_budget_mb=budget), 1000, pixels, texels)


def test_ao_params_follow_the_objects_size_and_lowest_point():
    positions = np.array([[0.0, 0.0, -2.0], [3.0, 4.0, 10.0], [1.0, 1.0, 1.0]])
    size = np.linalg.norm([3.0, 4.0, 12.0])
    params = ao_params(BakeSettings(quality="CUSTOM", rays=32, use_ground_plane=True), positions)
    assert params.rays == 32 and params.max_distance == pytest.approx(0.5 * size)
    assert params.offset == pytest.approx(1e-5 * size) and params.ground_height == -2.0
    fixed = ao_params(BakeSettings(auto_distance=False, max_distance=0.25), positions, rays=4)
    assert fixed.max_distance == 0.25 and fixed.rays == 4 and fixed.ground_height is None


def test_settle_pilot_stops_only_agreeing_points_and_scales_them_to_every_ray():
    params = AOParams(rays=64)                                       # 16 pilot rays
    sums = np.array([0.0, 16.0, 5.0, 0.0])
    decided = settle_pilot(sums, params, 16, neighbours=lambda code: np.array([True, True, True, False]))
    assert decided.tolist() == [True, True, False, False]
    assert sums.tolist() == [0.0, 64.0, 5.0, 0.0]
    unchanged = np.array([0.0, 16.0])
    assert not settle_pilot(unchanged, AOParams(rays=64, adaptive=False), 16).any()
    assert unchanged.tolist() == [0.0, 16.0]


def test_export_settings_are_validated_like_bake_settings():
    assert ExportSettings().size == 1024 and ExportSettings().domain == "CORNER"
    with pytest.raises(SeamlessAOError, match="size must be at least 8"):
        ExportSettings.from_kwargs(size=4)
    with pytest.raises(SeamlessAOError, match="domain must be one of CORNER, POINT"):
        ExportSettings.from_kwargs(domain="FACE")
    with pytest.raises(SeamlessAOError, match="Unknown setting"):
        ExportSettings.from_kwargs(rays=3)


def test_segment_distance_of_collinear_segments_is_their_gap():
    # On one line, far apart: the lines' "crossing" is ill-conditioned (parameters 0 / tiny); a
    # distance of 0 there made the injectivity check split charts at boundaries that never meet.
    rng = np.random.default_rng(0)
    direction = np.array([1.0, 0.5685])
    t = np.sort(rng.uniform(0, 1, (20000, 4)), axis=1)
    p0, p1, q0, q1 = (t[:, [k]] * direction for k in (2, 3, 0, 1))
    distance, _, _ = segment_distance(p0, p1, q0, q1)
    assert np.allclose(distance, (t[:, 2] - t[:, 1]) * np.linalg.norm(direction), rtol=0, atol=1e-12)
    # crossing segments still meet
    cross, s, u = segment_distance(np.array([[0.0, 0.0]]), np.array([[2.0, 2.0]]),
                                   np.array([[0.0, 2.0]]), np.array([[2.0, 0.0]]))
    assert cross[0] < 1e-12 and abs(s[0] - 0.5) < 1e-12 and abs(u[0] - 0.5) < 1e-12


def test_triangle_angles_are_the_law_of_cosines_angles_and_sum_to_pi():
    rng = np.random.default_rng(4)
    corners = rng.normal(0, 1, (2000, 3, 2)) * rng.uniform(1e-3, 1e3, (2000, 1, 1))
    angles = triangle_angles(corners)
    side = [np.linalg.norm(corners[:, (i + 2) % 3] - corners[:, (i + 1) % 3], axis=1) for i in range(3)]   # opposite i
    for i in range(3):
        b, c = side[(i + 1) % 3], side[(i + 2) % 3]
        cosine = np.clip((b * b + c * c - side[i] * side[i]) / (2 * b * c), -1, 1)
        assert np.allclose(angles[:, i], np.arccos(cosine), atol=1e-6)
    assert np.allclose(angles.sum(axis=1), np.pi)
    # both windings, and a right angle where the corners say so
    square = triangle_angles(np.array([[[0.0, 0.0], [2.0, 0.0], [0.0, 1.0]], [[0.0, 0.0], [0.0, 1.0], [2.0, 0.0]]]))
    assert np.allclose(square[:, 0], np.pi / 2) and np.allclose(square[0, 1:], square[1, [2, 1]])


def test_sanitized_normals_are_unit_and_replace_only_what_cannot_be_a_normal():
    rng = np.random.default_rng(8)
    triangles = 400
    given = rng.normal(0, 1, (triangles, 3, 3)) * rng.uniform(1e-6, 1e6, (triangles, 3, 1))
    broken = rng.choice(4, (triangles, 3), p=[0.85, 0.05, 0.05, 0.05])      # 1 zero, 2 NaN, 3 infinite
    given[broken == 1] = 0.0
    given[broken == 2, 0] = np.nan
    given[broken == 3, 2] = -np.inf
    face = rng.normal(0, 1, (triangles, 3))
    face /= np.linalg.norm(face, axis=1)[:, None]
    face[rng.random(triangles) < 0.1] = 0.0                                 # degenerate triangles
    normals = sanitized_normals(given, face)
    for t in range(triangles):
        for c in range(3):
            if broken[t, c] == 0:
                expected = given[t, c] / np.linalg.norm(given[t, c])
            elif face[t].any():
                expected = face[t]
            else:
                expected = np.array([0.0, 0.0, 1.0])
            assert np.allclose(normals[t, c], expected, rtol=0, atol=1e-12)
    assert np.allclose(np.linalg.norm(normals, axis=2), 1.0, rtol=0, atol=1e-12)


def random_layout(rng, count, corners=3):
    """Shapes of mixed sizes (many small, a few huge), in groups 0..3 and -1 (left out)."""
    start = rng.uniform(0, 20, (count, 1, 2))
    size = np.where(rng.random(count) < 0.05, rng.uniform(3, 12, count), rng.exponential(0.4, count))
    shapes = start + rng.normal(0, 1, (count, corners, 2)) * size[:, None, None]
    return shapes, rng.integers(-1, 4, count)


@pytest.mark.parametrize("seed, corners, margin", [(0, 3, 0.0), (1, 3, 0.3), (2, 2, 2.0), (3, 2, 0.0), (4, 3, 1.0)])
def test_candidate_pairs_miss_no_pair_whose_boxes_come_within_the_margin(seed, corners, margin):
    """Against every pair, brute force (tests/support/plane_judge.py): each pair of one group whose boxes come
    within the margin is a candidate, with or without a query, and nothing else is."""
    from plane_judge import boxes_within, boxes_within_brute
    rng = np.random.default_rng(seed)
    shapes, group = random_layout(rng, 700, corners)
    expected = boxes_within_brute(shapes, group, margin)
    assert len(expected) > 100
    assert np.array_equal(boxes_within(shapes, group, margin), expected)          # the judge's own sweep agrees
    found = candidate_pairs(shapes, group, margin)
    missed = set(map(tuple, expected)) - set(map(tuple, found))
    assert not missed, sorted(missed)[:5]
    assert np.array_equal(found, expected)
    query = rng.random(len(shapes)) < 0.1
    asked = candidate_pairs(shapes, group, margin, query=query)
    assert np.array_equal(asked, expected[query[expected[:, 0]] | query[expected[:, 1]]])


@pytest.mark.parametrize("seed, corners, margin, spread", [(0, 2, 0.5, 0.8), (1, 3, 0.3, 0.0), (2, 2, 2.0, 2.5),
                                                          (3, 2, 0.0, 1.0), (4, 2, 1.0, -1.0)])
def test_candidate_pairs_by_depth_are_the_pairs_within_the_margin_whose_depths_spread_further(
        seed, corners, margin, spread):
    """With depths, against the brute-force judge: exactly the pairs whose boxes come within the margin and whose
    depth spread (deepest of one less shallowest of the other) exceeds ``spread``, with or without a query; some
    shapes have depth ranges wider than the spread, some share one depth."""
    from plane_judge import boxes_within_brute
    rng = np.random.default_rng(seed)
    shapes, group = random_layout(rng, 700, corners)
    depth = rng.normal(0, 1.5, (len(shapes), 1)) + rng.exponential(0.3, (len(shapes), corners))
    depth[rng.random(len(shapes)) < 0.1] = 0.25
    near = boxes_within_brute(shapes, group, margin)
    a, b = near[:, 0], near[:, 1]
    expected = near[np.maximum(depth[a].max(1) - depth[b].min(1), depth[b].max(1) - depth[a].min(1)) > spread]
    assert 100 < len(expected) < len(near) or spread < 0
    assert np.array_equal(candidate_pairs(shapes, group, margin, depth=depth, spread=spread), expected)
    query = rng.random(len(shapes)) < 0.1
    asked = candidate_pairs(shapes, group, margin, query=query, depth=depth, spread=spread)
    assert np.array_equal(asked, expected[query[expected[:, 0]] | query[expected[:, 1]]])
    assert not len(candidate_pairs(shapes, group, margin, query=query & False, depth=depth, spread=spread))


def test_the_layout_judge_on_closed_form_cases():
    """tests/support/plane_judge.py, which judges layouts in other tests, on cases with known answers."""
    from plane_judge import interiors_overlap, overlap_point, triangle_distance
    base = np.array([[0.0, 0.0], [2.0, 0.0], [0.0, 2.0]])
    cases = np.array([
        [[2.0, 0.0], [0.0, 2.0], [2.0, 2.0]],        # shares an edge: touching, no overlap
        [[0.5, 0.5], [3.0, 0.5], [0.5, 3.0]],        # a corner inside: overlap
        [[-1.0, 1.0], [3.0, 0.5], [3.0, 1.0]],       # edges cross, no corner inside: overlap
        [[3.0, 0.0], [5.0, 0.0], [3.0, 2.0]],        # one unit to the right of the far corner
        [[0.2, 0.2], [0.4, 0.2], [0.2, 0.4]],        # inside the other entirely
    ])
    first = np.repeat(base[None], len(cases), axis=0)
    assert interiors_overlap(first, cases).tolist() == [False, True, True, False, True]
    assert np.allclose(triangle_distance(first, cases), [0.0, 0.0, 0.0, 1.0, 0.0])
    point = overlap_point(first[[1, 4]], cases[[1, 4]])
    assert np.allclose(point[1], cases[4].mean(axis=0))          # the small one's corners: its own centroid
    assert (point[0] > 0.5).all() and point[0].sum() < 2.0        # inside both


def test_candidate_pairs_with_a_query_are_the_pairs_that_touch_it():
    rng = np.random.default_rng(3)
    start = rng.uniform(0, 10, (400, 2))
    segments = np.stack([start, start + rng.normal(0, 0.3, (400, 2))], axis=1)
    group = rng.integers(-1, 3, 400)
    query = rng.random(400) < 0.1
    every = candidate_pairs(segments, group, 0.5)
    some = candidate_pairs(segments, group, 0.5, query=query)
    expected = every[query[every[:, 0]] | query[every[:, 1]]]
    assert len(expected) > 20 and np.array_equal(some, expected)


def test_without_flat_groups_drops_only_groups_whose_depth_spread_is_under_every_tolerance():
    group = np.array([0, 0, 2, 2, 3, 3, 5])
    depth = np.array([[1.0, 1.0], [1.0, 1.0 + 1e-12],          # 0: flat
                      [1.0, 1.0], [1.0, 1.0 + 2e-9],           # 2: one segment's tolerance is below its spread
                      [5.0, 5.0], [5.0, 5.0 + 5e-10],          # 3: flat
                      [2.0, 3.0]])                             # 5: alone, but sloped
    tolerance = np.array([1e-9, 1e-9, 1e-9, 1e-10, 1e-9, 1e-9, 1e-9])
    assert without_flat_groups(group, depth, tolerance).tolist() == [-1, -1, 2, 2, -1, -1, 5]
    assert without_flat_groups(np.zeros(0, dtype=np.int64), np.zeros((0, 2)), np.zeros(0)).shape == (0,)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_density_filling_is_the_plain_bisection_over_every_chart(seed):
    rng = np.random.default_rng(seed)
    extent = np.exp(rng.uniform(-4, 1, (3000, 2)))                 # points, small and large charts at once
    extent[:20] = extent[:1]                                        # repeats share every step change

    def footprint(density, padding):
        """Boxes as the packing module's doc states them, written out chart by chart."""
        total = 0.0
        for width, height in extent * density:
            if max(width, height) < 1.0:
                total += 1.0
                continue
            w, h = max(np.ceil(width - 1e-9), 1.0) + 2, max(np.ceil(height - 1e-9), 1.0) + 2
            if min(width, height) > SMALL_TEXELS:                     # xatlas' padding on each side, shared
                w, h = w + 2 * padding - 1, h + 2 * padding - 1
            total += w * h
        return total

    for padding, texels in ((2, 256.0**2), (4, 0.8 * 1024.0**2)):
        low, high = 0.01, 4096.0
        for _ in range(40):
            mid = np.sqrt(low * high)
            low, high = (mid, high) if footprint(mid, padding) <= texels else (low, mid)
        assert density_filling(extent, padding, texels, 0.01, 4096.0) == low


@pytest.mark.parametrize("seed", [0, 1])
def test_grow_labels_gives_each_node_its_nearest_source_in_hops_ties_to_the_smaller_label(seed):
    rng = np.random.default_rng(seed)
    count = 400
    edges = np.unique(np.sort(rng.integers(0, count, (900, 2)), axis=1), axis=0)
    edges = edges[edges[:, 0] != edges[:, 1]]
    side = rng.integers(0, 3, count)                          # labels cross only edges within one side
    labels = np.full(count, -1, dtype=np.int64)
    sources = rng.choice(count, 25, replace=False)
    labels[sources] = rng.permutation(25)
    grown = Adjacency(count, edges).grow_labels(labels.copy(), lambda s, t: side[s] == side[t])

    # plain breadth-first search from every source alone, edge by edge
    neighbours = [[] for _ in range(count)]
    for a, b in edges:
        if side[a] == side[b]:
            neighbours[a].append(b)
            neighbours[b].append(a)
    best = [(np.inf, -1)] * count
    for source in sources:
        hops = {source: 0}
        queue = [source]
        for node in queue:
            for other in neighbours[node]:
                if other not in hops:
                    hops[other] = hops[node] + 1
                    queue.append(other)
        for node, distance in hops.items():
            best[node] = min(best[node], (distance, labels[source]))
    assert grown.tolist() == [label for _, label in best]
    assert (grown >= 0).sum() > 200                            # most nodes are reached


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_without_quiet_sides_keeps_both_sides_of_every_pair_spread_more_than_the_margin_in_depth(seed):
    rng = np.random.default_rng(seed)
    start = rng.uniform(0, 10, (600, 2))
    seg = np.stack([start, start + rng.normal(0, 0.2, (600, 2))], axis=1)
    # a gentle slope, with a few steps and spikes a margin or more deep
    base = 0.05 * start[:, :1] + rng.normal(0, 0.01, (600, 1))
    seg_depth = base + np.where(rng.random((600, 1)) < 0.05, rng.uniform(0.3, 1.0, (600, 1)), 0.0) + [0.0, 0.01]
    seg_group = rng.integers(-1, 3, 600)
    margin = 0.25
    loud = without_quiet_sides(seg, seg_depth, seg_group, margin)
    assert np.array_equal(loud[loud >= 0], seg_group[loud >= 0]) and (loud[seg_group < 0] == -1).all()
    low, high = seg.min(axis=1), seg.max(axis=1)
    a, b = np.triu_indices(600, 1)
    gap = np.maximum(low[a] - high[b], low[b] - high[a]).max(axis=1)
    spread = np.maximum(seg_depth[a].max(axis=1) - seg_depth[b].min(axis=1),
                        seg_depth[b].max(axis=1) - seg_depth[a].min(axis=1))
    must = (gap <= margin) & (spread > margin) & (seg_group[a] == seg_group[b]) & (seg_group[a] >= 0)
    assert must.sum() > 10
    assert (loud[a[must]] >= 0).all() and (loud[b[must]] >= 0).all()
    assert (loud == -1).sum() > (seg_group == -1).sum() + 100          # and it does leave most sides out


@pytest.mark.parametrize("spans", [(7, 300, 5), (2**40, 2**30, 3)], ids=["folded", "too-wide-to-fold"])
def test_sort_order_is_lexsort_most_significant_first(spans):
    rng = np.random.default_rng(4)
    keys = [rng.integers(0, span, 5000) for span in spans]
    keys[1][::7] = keys[1][0]                   # plenty of ties, which must keep their input order
    assert np.array_equal(sort_order(*keys), np.lexsort(keys[::-1]))
    assert sort_order(np.zeros(0, dtype=np.int64)).shape == (0,)


def test_sample_repeat_hits_texel_centres_blends_between_them_and_wraps():
    values = np.random.default_rng(3).random((4, 6))
    uv = texel_uv(6, 4)
    assert uv.shape == (4, 6, 2) and np.allclose(sample_repeat(values, uv), values)
    assert np.allclose(sample_repeat(values, uv + [2.0, -1.0]), values)                 # repeats both ways
    between = (uv[1, 2] + uv[1, 3]) / 2
    assert np.isclose(sample_repeat(values, between), (values[1, 2] + values[1, 3]) / 2)
    edge = np.array([0.0, uv[2, 0, 1]])                                                  # u = 0: half way round
    assert np.isclose(sample_repeat(values, edge), (values[2, 0] + values[2, 5]) / 2)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_weld_vertices_joins_exactly_the_vertices_that_share_a_cell_of_a_shifted_grid(seed):
    """Against the rule the docstring states, pair by pair: two vertices of one group weld when some grid
    of cells ``tolerance`` wide, shifted by 0 or half a cell on each axis, holds both, and chains weld;
    indices numbered in order of first occurrence.  Exact repeats, near repeats, a crowd, walls that share a
    coordinate, groups with tolerances of their own."""
    rng = np.random.default_rng(seed)
    base = rng.uniform(0.0, 1.0, (300, 3))
    base[:60, 0] = 0.25                                                # a wall: one x for many vertices
    base[60:100, 2] = 0.75                                             # a floor
    tolerance_of_group = np.array([1e-3, 4e-3, 2e-4])
    near = base[rng.integers(0, 300, 250)] + rng.uniform(-6e-4, 6e-4, (250, 3))
    # a crowd: more vertices within a cell of each other than the prune measures pair by pair
    crowd = base[0] + rng.uniform(-3e-3, 3e-3, (40, 3))
    positions = np.concatenate([base, base[rng.integers(0, 300, 100)], near, crowd])     # exact repeats too
    positions = positions[rng.permutation(len(positions))]
    groups = rng.integers(0, 3, len(positions))
    groups[:] = np.where(rng.random(len(positions)) < 0.7, 0, groups)
    tolerance = tolerance_of_group[groups]
    welded = weld_vertices(positions, tolerance, groups)

    low = np.array([positions[groups == g].min(axis=0) for g in range(3)])
    cell = (positions - low[groups]) / tolerance[:, None]
    count = len(positions)
    parent = list(range(count))

    def root(x):
        while parent[x] != x:
            x = parent[x]
        return x

    a, b = np.triu_indices(count, 1)
    same_group = groups[a] == groups[b]
    for shift in np.ndindex(2, 2, 2):
        index = np.floor(cell + 0.5 * np.array(shift))
        shared = same_group & (index[a] == index[b]).all(axis=1)
        for x, y in zip(a[shared], b[shared]):
            x, y = root(x), root(y)
            if x != y:
                parent[max(x, y)] = min(x, y)
    roots = [root(x) for x in range(count)]
    numbering = {}
    expected = [numbering.setdefault(r, len(numbering)) for r in roots]
    assert welded.tolist() == expected
    assert count - len(numbering) > 150                                # plenty did weld
    within_half = same_group & (np.abs(positions[a] - positions[b]) <= 0.5 * tolerance[a, None]).all(axis=1)
    assert (welded[a[within_half]] == welded[b[within_half]]).all()


@pytest.mark.parametrize("vertices", [6, 40, 1 << 40])
def test_duplicate_triangle_count_counts_repeats_of_a_vertex_set_in_any_order(vertices):
    """Against a set of sorted vertex triples: a triangle is a duplicate when an earlier one has its three
    vertices in any order (either winding); with 2**40 vertex ids the keys cannot fold into one int64."""
    rng = np.random.default_rng(vertices % 97)
    base = rng.choice(min(vertices, 1 << 20), (300, 3), replace=True) * (vertices // min(vertices, 1 << 20))
    base = base[(base[:, 0] != base[:, 1]) & (base[:, 1] != base[:, 2]) & (base[:, 0] != base[:, 2])]
    repeats = base[rng.integers(0, len(base), 120)]
    repeats = np.take_along_axis(repeats, np.argsort(rng.random(repeats.shape), axis=1), axis=1)  # any order
    triangles = np.concatenate([base, repeats])[rng.permutation(len(base) + 120)]
    seen, expected = set(), 0
    for triangle in triangles:
        key = tuple(sorted(int(v) for v in triangle))
        expected += key in seen
        seen.add(key)
    assert expected >= 100
    assert duplicate_triangle_count(triangles) == expected
    assert duplicate_triangle_count(np.zeros((0, 3), dtype=np.int64)) == 0


def test_row_blocks_cover_the_rows_in_order_once(monkeypatch):
    monkeypatch.setattr(blocks, "BLOCK_ROWS", 4)
    assert blocks.row_blocks(10) == [slice(0, 4), slice(4, 8), slice(8, 10)]
    assert blocks.row_blocks(8) == [slice(0, 4), slice(4, 8)] and blocks.row_blocks(0) == []
