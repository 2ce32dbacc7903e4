"""Issue 13: every real asset packs at every image size, and the layout stays correct.

The generated stand-ins of :mod:`real_assets` (an interior of 1,000+ pieces,
a holed 100k-triangle scan, 10,000 chips, a 1:1000 beam) must lay out at
256², 512² and 1024² with no exception; every surface point's bilinear
footprint must read filled texels that sample its own chart; no two charts
may share texels, except one-texel charts that had to share with a warning.
"""

import numpy as np
import pytest

import real_assets
from seamless_ao.core.mesh.triangle_mesh import TriangleMesh
from seamless_ao.core.atlas.packing import Packer
from seamless_ao.core.layout import build_layout, layer_lookup
from seamless_ao.core.atlas.raster import texel_geometry
from layout_checks import random_surface_points, texel_table


@pytest.fixture(scope="module", params=sorted(real_assets.ASSETS))
def asset(request):
    positions, triangles = real_assets.ASSETS[request.param]()
    return request.param, TriangleMesh.from_triangles(positions, triangles)


def check_footprints(layout, rng, count=4000):
    """Bilinear footprints of random surface points read filled texels of the point's own chart."""
    mesh, atlas = layout.mesh, layout.atlas
    triangle, bary, _ = random_surface_points(mesh, count, rng, per_triangle=True)
    uv = layer_lookup(atlas, mesh, triangle, bary)
    table = texel_table(layout)
    texel_chart = atlas.member_chart[layout.texels.member]
    for layer in range(3):
        member = np.where(atlas.membership[triangle, layer] >= 0, atlas.membership[triangle, layer],
                          atlas.dominant_member[triangle])
        chart = atlas.member_chart[member]
        one_texel = atlas.chart_texel[chart] >= 0
        pixel = uv[:, layer] * atlas.size - 0.5
        x0, y0 = np.floor(pixel[:, 0]).astype(np.int64), np.floor(pixel[:, 1]).astype(np.int64)
        fx, fy = pixel[:, 0] - x0, pixel[:, 1] - y0
        for dx, wx in ((0, 1 - fx), (1, fx)):
            for dy, wy in ((0, 1 - fy), (1, fy)):
                read = (wx * wy) > 1e-6
                flat = (y0 + dy) * atlas.width + (x0 + dx)
                found = table[flat]
                assert (found[read] >= 0).all(), "bilinear filtering reads an empty texel (layer {})".format(layer)
                # what is read belongs to the same chart (one-texel charts that share: their own texel)
                own = (texel_chart[found[read]] == chart[read]) | (
                    one_texel[read] & (atlas.chart_texel[chart[read]] == flat[read]))
                assert own.all(), "bilinear filtering reads another chart's texel (layer {})".format(layer)
    points, normals, _ = texel_geometry(layout.texels, atlas, mesh)
    assert np.isfinite(points).all() and np.isfinite(normals).all()
    uv_all = atlas.layer_uv()
    assert np.isfinite(uv_all).all() and uv_all.min() > 0.0 and uv_all.max() < 1.0


def check_one_texel_charts(layout):
    """Each one-texel chart has its UVs at its texel's centre, and that texel samples the chart."""
    atlas = layout.atlas
    point = atlas.chart_texel >= 0
    if not point.any():
        return
    members = np.flatnonzero(point[atlas.member_chart])
    texel = atlas.chart_texel[atlas.member_chart[members]]
    centre = np.stack([texel % atlas.width + 0.5, texel // atlas.width + 0.5], axis=1)
    assert np.abs(atlas.member_uv[members] - centre[:, None]).max() < 1e-9
    table = texel_table(layout)
    sampled = layout.texels.member[table[atlas.chart_texel[point]]]
    if not any("share texels" in w for w in atlas.warnings):
        assert len(np.unique(atlas.chart_texel[point])) == point.sum(), "one-texel charts share a texel"
        assert (atlas.member_chart[sampled] == np.flatnonzero(point)).all()


@pytest.mark.parametrize("size", [256, 512, 1024])
def test_asset_lays_out_at_every_size(asset, size):
    name, mesh = asset
    layout = build_layout(mesh, image_size=size)
    assert layout.atlas.width == layout.atlas.height == size
    assert layout.atlas.density > 0
    check_footprints(layout, np.random.default_rng(size))
    check_one_texel_charts(layout)


def test_the_generated_interior_has_what_made_the_old_packer_give_up():
    """The stand-in is what it stands for: 1,000+ pieces and 60k+ triangles (that it lays out at every size
    is :func:`test_asset_lays_out_at_every_size`'s)."""
    mesh = TriangleMesh.from_triangles(*real_assets.interior())
    from seamless_ao.core.mesh.adjacency import face_adjacency
    topology = face_adjacency(mesh)
    edges = topology.face_edges
    parent = np.arange(mesh.face_count)
    # pieces: union-find over shared edges, vectorised by repeated label propagation
    for _ in range(64):
        low = np.minimum(parent[edges[:, 0]], parent[edges[:, 1]])
        np.minimum.at(parent, edges[:, 0], low)
        np.minimum.at(parent, edges[:, 1], low)
        parent = parent[parent]
    assert len(np.unique(parent)) >= 1000
    assert len(mesh.triangles) >= 60_000


def test_more_tiny_pieces_than_texels_share_texels_with_a_warning():
    """20,000 chips (80,000 charts) in a 256² image: they cannot each have a texel; bake anyway, say so."""
    positions, triangles = real_assets.chips(count=20_000)
    mesh = TriangleMesh.from_triangles(positions, triangles)
    layout = build_layout(mesh, image_size=256)
    warnings = layout.atlas.warnings
    assert len(warnings) == 1 and "share texels" in warnings[0] and "512x512" in warnings[0]
    check_footprints(layout, np.random.default_rng(7))
    check_one_texel_charts(layout)
    # at 512² each has its own texel and nothing is said
    assert build_layout(mesh, image_size=512).atlas.warnings == []


def test_density_search_ends_next_to_a_density_that_does_not_fit(asset, monkeypatch):
    """The search converged: it tried a density at most 13% above its result, in the image, and that failed."""
    name, mesh = asset
    tried = []
    place = Packer.place

    def recorded(self, density, resolution, share):
        placement = place(self, density, resolution, share)
        tried.append((density, resolution, placement is not None))
        return placement

    monkeypatch.setattr(Packer, "place", recorded)
    atlas = build_layout(mesh, image_size=512).atlas
    assert not (atlas.chart_texel >= 0).all()             # at 512² every asset has charts wider than a texel
    final = atlas.density
    assert any(fits and density == final for density, resolution, fits in tried if resolution == 512)
    failed_above = [density for density, resolution, fits in tried
                    if resolution == 512 and not fits and final < density <= final * 1.13]
    assert failed_above, "the search stopped with no failure just above"


def test_long_charts_are_cut_so_a_long_part_does_not_set_the_density():
    """The 1000-unit beam's side charts are cut: no chart is longer than a quarter of the image at the
    expected density, so the beam spans several image widths instead of one texel across."""
    positions, triangles = real_assets.long_thin()
    mesh = TriangleMesh.from_triangles(positions, triangles)
    layout = build_layout(mesh, image_size=1024)
    assert 1000.0 * layout.atlas.density > 4 * 1024
    uv = layout.atlas.member_uv
    low = np.full((layout.charts.count, 2), np.inf)
    high = np.full((layout.charts.count, 2), -np.inf)
    np.minimum.at(low, layout.atlas.member_chart, uv.min(axis=1))
    np.maximum.at(high, layout.atlas.member_chart, uv.max(axis=1))
    assert (high - low).max() <= 1024 / 2


def test_cutting_keeps_each_piece_on_its_axis_and_every_face_in_a_chart():
    from seamless_ao.core.mesh.adjacency import face_adjacency
    from seamless_ao.core.charts.clustering import cluster_faces, cut_long_charts
    positions, triangles = real_assets.long_thin(segments=200)
    mesh = TriangleMesh.from_triangles(positions, triangles)
    charts = cluster_faces(mesh, face_adjacency(mesh))
    cut = cut_long_charts(mesh, charts, 50.0)
    assert cut.count > charts.count + 4 * 15                     # four long sides, 20 pieces each at least
    assert ((cut.chart_of_face >= 0) == (charts.chart_of_face >= 0)).all()
    has = charts.chart_of_face >= 0
    assert (cut.chart_axis[cut.chart_of_face[has]] == charts.chart_axis[charts.chart_of_face[has]]).all()
    assert cut_long_charts(mesh, charts, 2000.0) is charts        # nothing long: unchanged


# -- accuracy: the baked result against the plain reference ----------------------------------------

