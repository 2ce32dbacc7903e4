"""Issue 4: charts to one packed atlas with exact texel points and normals."""

import numpy as np
import pytest

import meshes
from blender_scenes import suzanne
from conftest import seamless_ao  # noqa: F401
from seamless_ao.core.clustering import AXES
from seamless_ao.core.errors import SeamlessAOError
from seamless_ao.core.mesh import TriangleMesh
from seamless_ao.core.overlap import candidate_pairs, separated
from seamless_ao.core.pipeline import build_layout, layer_lookup
from seamless_ao.core.raster import COVERED, texel_geometry


def random_surface_points(mesh, count, rng, per_triangle=False):
    """Random points: triangle (k,), barycentrics (k, 3), positions (k, 3).

    Area-weighted, or (``per_triangle``) every non-degenerate triangle equally
    likely, so slivers get their share.
    """
    weight = np.where(mesh.degenerate, 0.0, 1.0 if per_triangle else mesh.triangle_area)
    triangle = rng.choice(len(weight), size=count, p=weight / weight.sum())
    r1, r2 = rng.random(count), rng.random(count)
    s = np.sqrt(r1)
    bary = np.stack([1 - s, s * (1 - r2), s * r2], axis=1)
    points = np.einsum("kc,kcd->kd", bary, mesh.positions[mesh.triangles[triangle]])
    return triangle, bary, points


def texel_table(layout):
    """Dense map texel -> position in ``layout.texels`` (-1 where empty)."""
    atlas, texels = layout.atlas, layout.texels
    table = np.full(atlas.width * atlas.height, -1, dtype=np.int64)
    table[texels.index] = np.arange(len(texels))
    return table


def check_lookups(layout, rng, count=3000, per_triangle=False):
    """Random surface points: bilinear footprints are filled and the nearest texel samples the point."""
    mesh, atlas = layout.mesh, layout.atlas
    triangle, bary, points = random_surface_points(mesh, count, rng, per_triangle)
    uv = layer_lookup(atlas, mesh, triangle, bary)
    table = texel_table(layout)
    size = atlas.size
    for layer in range(3):
        pixel = uv[:, layer] * size - 0.5                       # bilinear footprint, as Blender samples
        x0, y0 = np.floor(pixel[:, 0]).astype(int), np.floor(pixel[:, 1]).astype(int)
        for dx in (0, 1):
            for dy in (0, 1):
                found = table[(y0 + dy) * atlas.width + (x0 + dx)]
                assert (found >= 0).all(), "bilinear filtering reads an empty texel (layer {})".format(layer)
        nearest = np.floor(uv[:, layer] * size).astype(int)
        found = table[nearest[:, 1] * atlas.width + nearest[:, 0]]
        texel_points, _, _ = texel_geometry(layout.texels, atlas, mesh, found)
        member = np.where(atlas.membership[triangle, layer] >= 0, atlas.membership[triangle, layer],
                          atlas.dominant_member[triangle])
        signed_axis = layout.charts.chart_axis[atlas.member_chart[member]]
        sampled = atlas.member_triangle[layout.texels.member[found]]
        cos = np.minimum(np.abs((mesh.triangle_normal[triangle] * AXES[signed_axis]).sum(1)),
                         np.abs((mesh.triangle_normal[sampled] * AXES[signed_axis]).sum(1)))
        # The texel centre is within 0.71 texel of the point in the chart plane.  A covered
        # texel samples its centre: within 0.71 texel.  A near texel samples the point of its
        # nearest triangle closest to the centre, no farther from the centre than the point:
        # within 1.42 texels.  The plane stretches by 1 / cos(angle to the chart axis) on the surface.
        limit = np.where(layout.texels.kind[found] == COVERED, 0.71, 1.42) + 1e-6
        texel_size = 1.0 / atlas.density / cos
        distance = np.linalg.norm(texel_points - points, axis=1) / texel_size
        assert (distance <= limit).all(), "a lookup lands {:.3g} texels from its point".format(
            (distance / limit).max())


def check_layers_do_not_overlap(layout):
    """Within one UV layer, distinct triangles never overlap, and charts keep 2 texels apart."""
    mesh, atlas = layout.mesh, layout.atlas
    live = ~mesh.degenerate
    for layer in range(3):
        member = np.where(atlas.membership[:, layer] >= 0, atlas.membership[:, layer], atlas.dominant_member)
        tri_uv = atlas.member_uv[member][live]
        chart = atlas.member_chart[member][live]
        pairs = candidate_pairs(tri_uv, np.zeros(len(tri_uv), dtype=np.int64), margin=2.0)
        a, b = pairs[:, 0], pairs[:, 1]
        same_chart = chart[a] == chart[b]
        # different charts: at least two texels apart
        far = separated(tri_uv[a[~same_chart]], tri_uv[b[~same_chart]], 1.999)
        assert far.all(), "charts closer than 2 texels in layer {}".format(layer)
        # same chart, not neighbours: interiors must not overlap
        welded = layout.topology.welded_triangles[live]
        shares = (welded[a][:, :, None] == welded[b][:, None, :]).any(axis=(1, 2))
        inner = same_chart & ~shares
        apart = separated(tri_uv[a[inner]], tri_uv[b[inner]], -1e-6)
        assert apart.all(), "two triangles overlap in layer {}".format(layer)


def check_texels_finite(layout):
    points, normals, geometric = texel_geometry(layout.texels, layout.atlas, layout.mesh)
    assert np.isfinite(points).all() and np.isfinite(normals).all()
    assert np.allclose(np.linalg.norm(normals, axis=1), 1.0)
    uv = layout.atlas.layer_uv()
    assert np.isfinite(uv).all() and uv.min() > 0.0 and uv.max() < 1.0


@pytest.fixture(scope="module")
def suzanne_layout():
    import bpy
    from seamless_ao.operators.mesh_data import read_triangles
    bpy.ops.wm.read_factory_settings(use_empty=True)
    mesh, _ = read_triangles(suzanne(2).data)
    return build_layout(mesh, image_size=512)


def test_suzanne_lookups_and_layers(suzanne_layout):
    layout = suzanne_layout
    assert layout.atlas.width == layout.atlas.height == 512
    assert 0.3 < layout.atlas.utilisation <= 1.0
    check_lookups(layout, np.random.default_rng(1))
    check_layers_do_not_overlap(layout)
    check_texels_finite(layout)


@pytest.mark.parametrize("make", [
    lambda: meshes.uv_sphere(rings=24, segments=48),
    lambda: meshes.torus(),
    lambda: meshes.spiral_ramp(turns=2.0),
    lambda: meshes.box(size=(1.0, 1.0, 1e-4), subdivisions=2),
], ids=["sphere", "torus", "ramp", "thin-plate"])
def test_generated_meshes(make):
    mesh = TriangleMesh.from_triangles(*make(), smooth=True)
    layout = build_layout(mesh, image_size=256)
    check_lookups(layout, np.random.default_rng(2))
    check_layers_do_not_overlap(layout)
    check_texels_finite(layout)


def test_cube_texel_count_matches_area_at_density():
    density = 40.0
    mesh = TriangleMesh.from_triangles(*meshes.box(size=(1.0, 2.0, 0.5), subdivisions=3))
    layout = build_layout(mesh, density=density)
    atlas, texels = layout.atlas, layout.texels
    covered = texels.kind == COVERED
    face_of_texel = mesh.triangle_face[atlas.member_triangle[texels.member[covered]]]
    normal_axis = np.argmax(np.abs(mesh.face_normal), axis=1)[face_of_texel] * 2 + (
        mesh.face_normal[face_of_texel].max(axis=1) < 0.5)
    counts = np.bincount(normal_axis, minlength=6)
    side_area = {0: 2.0 * 0.5, 2: 1.0 * 0.5, 4: 1.0 * 2.0}
    side_perimeter = {0: 2.0 + 0.5, 2: 1.0 + 0.5, 4: 1.0 + 2.0}
    # the packed density may differ slightly from the request; use each chart's own scale
    for signed in range(6):
        chart = np.flatnonzero(layout.charts.chart_axis == signed)[0]
        member = np.flatnonzero(atlas.member_chart == chart)
        local_area = mesh.triangle_area[atlas.member_triangle[member]].sum()
        uv = atlas.member_uv[member]
        texel_area = 0.5 * np.abs((uv[:, 1, 0] - uv[:, 0, 0]) * (uv[:, 2, 1] - uv[:, 0, 1])
                                  - (uv[:, 2, 0] - uv[:, 0, 0]) * (uv[:, 1, 1] - uv[:, 0, 1])).sum()
        chart_density = np.sqrt(texel_area / local_area)
        expected = side_area[signed - signed % 2] * chart_density**2
        assert abs(chart_density / density - 1) < 0.1
        perimeter_texels = 2 * side_perimeter[signed - signed % 2] * chart_density
        # centres on a chart's border count as covered: up to half a perimeter extra
        assert abs(counts[signed] - expected) <= 0.5 * perimeter_texels + 4, (signed, counts[signed], expected)


def test_slivers_and_zero_area_triangles_leave_no_holes():
    rng = np.random.default_rng(3)
    positions, triangles = meshes.box(subdivisions=2)
    n = len(positions)
    # a fan of slivers (aspect ratio about 1e6) on a plate above the box, plus zero-area triangles
    fan_centre = np.array([0.0, 0.0, 1.0])
    angles = np.linspace(0, 2 * np.pi, 400, endpoint=False)
    rim = np.stack([np.cos(angles), np.sin(angles), np.ones_like(angles)], 1) * [0.8, 0.8, 1.0]
    sliver = np.array([[0.0, 0.0, 1.0], [0.9, 0.0, 1.0], [0.9, 1e-6, 1.0]]) + [0.0, 1.5, 0.0]
    extra_positions = np.vstack([fan_centre, rim, sliver, [[0, 3, 1], [0.5, 3, 1], [1, 3, 1]]])
    k = np.arange(len(angles))
    fan = np.stack([np.full(len(k), n), n + 1 + k, n + 1 + (k + 1) % len(k)], 1)
    s = n + 1 + len(angles)
    extra = np.vstack([fan, [[s, s + 1, s + 2]], [[s + 3, s + 4, s + 5]], [[s, s, s + 1]]])
    mesh = TriangleMesh.from_triangles(np.vstack([positions, extra_positions]), np.vstack([triangles, extra]))
    assert mesh.degenerate.sum() == 2
    layout = build_layout(mesh, image_size=256)
    check_lookups(layout, rng, per_triangle=True)
    check_texels_finite(layout)


def test_explicit_density_too_large_is_refused():
    mesh = TriangleMesh.from_triangles(*meshes.box())
    with pytest.raises(SeamlessAOError, match="lower the density"):
        build_layout(mesh, density=1e5)


def test_empty_mesh_is_refused():
    mesh = TriangleMesh(np.zeros((3, 3)), np.zeros((0, 3)), np.zeros(0), np.zeros((0, 3, 3)))
    with pytest.raises(SeamlessAOError, match="no faces"):
        build_layout(mesh)
