"""The rasteriser's shortcut: near texels come from the triangles on the border of what is drawn."""

import numpy as np
import pytest

from seamless_ao.core.mesh.triangle_mesh import TriangleMesh
from seamless_ao.core.atlas.raster import NEAR, closest_barycentric, point_keys, rasterise_triangles, rim_triangles


def grid(columns, rows, cell, jitter, seed, holes=0):
    """A jittered grid of quads (two triangles each) in texel coordinates, some cells removed.

    Returns ``uv`` (k, 3, 2) float64 with shared corners bit-identical, and ``corner`` (k, 3) int vertex ids.
    """
    rng = np.random.default_rng(seed)
    x, y = np.meshgrid(np.arange(columns + 1), np.arange(rows + 1))
    points = np.stack([x.ravel(), y.ravel()], axis=1) * cell + 3.0
    points += rng.uniform(-jitter, jitter, points.shape) * cell
    vertex = lambda i, j: j * (columns + 1) + i  # noqa: E731
    corners = []
    for j in range(rows):
        for i in range(columns):
            a, b, c, d = vertex(i, j), vertex(i + 1, j), vertex(i + 1, j + 1), vertex(i, j + 1)
            corners += [[a, b, c], [a, c, d]] if (i + j) % 2 else [[a, b, d], [b, c, d]]
    corners = np.array(corners)
    keep = np.ones(len(corners), dtype=bool)
    keep[rng.choice(len(corners), holes, replace=False)] = False
    return points[corners[keep]], corners[keep]


def brute_force_rim(uv):
    """A triangle is on the rim when a point just outside one of its sides lies in no triangle."""
    rim = np.zeros(len(uv), dtype=bool)
    for t, tri in enumerate(uv):
        centre = tri.mean(axis=0)
        for k in range(3):
            p, q = tri[k], tri[(k + 1) % 3]
            middle = 0.5 * (p + q)
            outward = middle - centre
            normal = np.array([q[1] - p[1], p[0] - q[0]])
            normal *= np.sign(normal @ outward) / np.linalg.norm(normal)
            probe = middle + 1e-7 * normal
            a, b, c = uv[:, 0], uv[:, 1], uv[:, 2]
            cross = lambda u, v: u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]  # noqa: E731
            s = np.stack([cross(b - a, probe - a), cross(c - b, probe - b), cross(a - c, probe - c)], axis=1)
            inside = (s > 0).all(axis=1) | (s < 0).all(axis=1)
            rim[t] |= not inside.any()
    return rim


@pytest.mark.parametrize("holes", [0, 9])
def test_rim_triangles_are_those_with_a_side_on_the_border(holes):
    uv, corner = grid(7, 5, 3.0, 0.2, seed=holes, holes=holes)
    rim = rim_triangles(corner)
    assert np.array_equal(rim, brute_force_rim(uv))
    assert 0 < rim.sum() < len(uv)                      # the grid has inner triangles
    assert np.array_equal(rim_triangles(point_keys(uv.reshape(-1, 2)).reshape(-1, 3)), rim)


def test_a_side_shared_the_same_way_round_is_a_border():
    # triangle 0's sides 1-2 and 2-0 are shared the right way round, but 0-1 only by a triangle
    # folded onto the same side (0-1 again, not 1-0): it is on the border
    corner = np.array([[0, 1, 2], [2, 1, 5], [0, 2, 6], [0, 1, 3]])
    assert rim_triangles(corner)[0]
    assert not rim_triangles(np.array([[0, 1, 2], [2, 1, 5], [0, 2, 6], [1, 0, 3]]))[0]
    # three triangles on one side: a run of three is never inside
    assert rim_triangles(np.array([[0, 1, 2], [1, 0, 3], [1, 0, 4]])).all()
    assert rim_triangles(np.array([[0, 1, 2], [1, 0, 3]])).all()        # each has two free sides


def sampled_distance(texels, uv):
    x = texels.index % texels.width + 0.5
    y = texels.index // texels.width + 0.5
    b = np.stack(closest_barycentric(uv[texels.member], x, y), axis=1)
    point = (b[:, :, None] * uv[texels.member]).sum(axis=1)
    return np.hypot(point[:, 0] - x, point[:, 1] - y)


@pytest.mark.parametrize("cell, jitter, holes", [(3.0, 0.25, 0), (0.7, 0.3, 11), (1.6, 0.45, 25)])
def test_near_texels_from_the_rim_are_those_from_every_triangle(cell, jitter, holes):
    uv, _ = grid(23, 17, cell, jitter, seed=holes, holes=holes)
    live = np.arange(len(uv))
    size = int(np.ceil(uv.max())) + 4
    shortcut = rasterise_triangles(uv, live, size, size, padding=2)
    every = rasterise_triangles(uv, live, size, size, padding=2, rim=np.ones(len(live), dtype=bool))
    assert np.array_equal(shortcut.index, every.index)
    assert np.array_equal(shortcut.kind, every.kind)
    assert (shortcut.kind == NEAR).sum() > 20
    near = shortcut.kind == NEAR
    # either way the texel samples a point its bilinear footprint reaches (the winner may differ
    # where a triangle off the rim scores as well as the rim's)
    assert sampled_distance(shortcut, uv)[near].max() <= np.sqrt(2.0) + 1e-9
    assert sampled_distance(every, uv)[near].max() <= np.sqrt(2.0) + 1e-9


@pytest.mark.parametrize("cell, snap", [(0.2, False), (0.2, True), (0.45, True), (2.5, False)])
def test_triangles_whose_box_holds_no_texel_centre_are_left_undrawn_and_nothing_changes(monkeypatch, cell, snap):
    """The covered pass skips triangles whose box holds no texel centre: the texels are those of drawing
    every triangle, member for member, on grids far finer than a texel (most boxes hold none), with corners
    moved onto texel centres (``snap``: crossings computed exactly at a corner) and coarser than a texel."""
    from seamless_ao.core.atlas import raster
    uv, _ = grid(40, 30, cell, 0.3, seed=int(cell * 10) + snap, holes=9)
    if snap:
        near_centre = np.abs(uv - (np.floor(uv) + 0.5)) < 0.05
        uv = np.where(near_centre, np.floor(uv) + 0.5, uv)       # shared corners stay bit-identical
    live = np.arange(len(uv))
    size = int(np.ceil(uv.max())) + 4
    skipping = rasterise_triangles(uv, live, size, size, padding=2)
    assert not raster.box_holds_texel_centre(uv, live).all() or cell > 1
    monkeypatch.setattr(raster, "box_holds_texel_centre", lambda triangles, chosen: np.ones(len(chosen), dtype=bool))
    drawing_all = rasterise_triangles(uv, live, size, size, padding=2)
    for name in ("index", "member", "kind", "ring"):
        assert np.array_equal(getattr(skipping, name), getattr(drawing_all, name)), name
    assert (skipping.kind == 0).sum() > 40


def test_box_test_block_by_block_answers_as_one_block(monkeypatch):
    """Blocks of 7 over the chosen triangles (the last one short) give each triangle the answer of one block."""
    from seamless_ao.core.arrays import blocks
    from seamless_ao.core.arrays.geometry2d import box_holds_texel_centre
    uv, _ = grid(12, 9, 0.45, 0.3, seed=3, holes=0)
    chosen = np.random.default_rng(2).permutation(len(uv))[:150]
    whole = box_holds_texel_centre(uv, chosen)
    monkeypatch.setattr(blocks, "BLOCK_ROWS", 7)
    assert 150 % 7 and np.array_equal(box_holds_texel_centre(uv, chosen), whole) and 0 < whole.sum() < len(whole)
    assert box_holds_texel_centre(uv, chosen[:0]).shape == (0,)


def test_rim_distance_is_the_distance_to_the_nearest_side_written_out_side_by_side():
    """The texel points moved off a crease are those closer to their triangle's border than the inset;
    the distance comes from each corner's height, checked against point-to-segment distances."""
    from seamless_ao.core.atlas.raster import _rim_distance
    rng = np.random.default_rng(5)
    positions = rng.normal(size=(300, 3))
    triangles = rng.integers(0, 300, (200, 3))
    triangles = triangles[(triangles[:, 0] != triangles[:, 1]) & (triangles[:, 1] != triangles[:, 2])
                          & (triangles[:, 0] != triangles[:, 2])]
    mesh = TriangleMesh.from_triangles(positions, triangles)
    triangle = rng.integers(0, len(triangles), 500)
    bary = rng.dirichlet([1.0, 1.0, 1.0], 500)
    bary[::7, 0] = 0.0                                                   # points on a side
    bary /= bary.sum(axis=1, keepdims=True)
    corners = positions[triangles[triangle]]
    point = np.einsum("kc,kcd->kd", bary, corners)
    expected = np.full(len(point), np.inf)
    for i in range(3):
        start, end = corners[:, (i + 1) % 3], corners[:, (i + 2) % 3]
        along = np.clip(((point - start) * (end - start)).sum(axis=1) / ((end - start) ** 2).sum(axis=1), 0, 1)
        expected = np.minimum(expected, np.linalg.norm(point - start - along[:, None] * (end - start), axis=1))
    found = _rim_distance(mesh, triangle, tuple(bary.T))
    assert np.allclose(found, expected, rtol=1e-9, atol=1e-12)
    assert (found[::7] <= 1e-12).all()


@pytest.mark.parametrize("seed", range(4))
def test_rim_triangles_count_each_side_both_ways_round(seed):
    """Against the definition, side by side: a side is inside when exactly two sides join its two corners and
    they run opposite ways.  Corners drawn from a few keys make shared, folded, tripled and pointless sides; one
    case has keys near 2**40, too large for two of them to fold into one int64 key."""
    rng = np.random.default_rng(seed)
    corner = rng.integers(0, 9, (60, 3))
    if seed == 3:
        corner = corner * (1 << 40) + 7
    uses = {}
    for a, b in zip(corner.ravel(), np.roll(corner, -1, axis=1).ravel()):
        uses.setdefault((min(a, b), max(a, b)), []).append((a < b, a > b))
    inside = [[a != b and len(uses[min(a, b), max(a, b)]) == 2 and
               uses[min(a, b), max(a, b)][0] != uses[min(a, b), max(a, b)][1]
               for a, b in zip(row, np.roll(row, -1))] for row in corner]
    assert np.array_equal(rim_triangles(corner), ~np.array(inside).all(axis=1))
    assert len(rim_triangles(corner[:0])) == 0
