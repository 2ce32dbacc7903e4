"""Checks shared by the chart and atlas tests: charts keep every promise of issue 3, lookups land on their
own chart, layers never overlap.  Overlaps and distances are judged by :mod:`plane_judge`, which shares no
code with the layout it judges."""

import numpy as np

from plane_judge import boxes_within, depth_at, interiors_overlap, overlap_point, triangle_distance
from seamless_ao.core.mesh.adjacency import face_adjacency
from seamless_ao.core.charts.clustering import AXES, NORMAL_SMOOTHING, SAME_SURFACE, cluster_faces
from seamless_ao.core.layout import layer_lookup
from seamless_ao.core.atlas.packing import chart_kinds as packing_chart_kinds
from seamless_ao.core.atlas.raster import COVERED, PADDING, RIM_TEXELS, texel_geometry


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
        # within 1.42 texels.  Either, on a triangle's rim, moves RIM_TEXELS of a texel (object units
        # on the surface) into it.  The plane stretches by 1 / cos(angle to the chart axis) on the surface.
        limit = np.where(layout.texels.kind[found] == COVERED, 0.71, 1.42) + RIM_TEXELS + 1e-6
        texel_size = 1.0 / atlas.density / cos
        distance = np.linalg.norm(texel_points - points, axis=1) / texel_size
        assert (distance <= limit).all(), "a lookup lands {:.3g} texels from its point".format(
            (distance / limit).max())


def check_layers_do_not_overlap(layout, separation=1.999):
    """Within one UV layer, distinct triangles never overlap, and charts keep ``separation`` texels apart."""
    mesh, atlas = layout.mesh, layout.atlas
    live = ~mesh.degenerate
    for layer in range(3):
        member = np.where(atlas.membership[:, layer] >= 0, atlas.membership[:, layer], atlas.dominant_member)
        tri_uv = atlas.member_uv[member][live]
        chart = atlas.member_chart[member][live]
        pairs = boxes_within(tri_uv, np.zeros(len(tri_uv), dtype=np.int64), separation)
        a, b = pairs[:, 0], pairs[:, 1]
        same_chart = chart[a] == chart[b]
        # different charts: at least two texels apart
        gap = triangle_distance(tri_uv[a[~same_chart]], tri_uv[b[~same_chart]])
        assert (gap > separation).all(), "charts {:.3g} texels apart in layer {}".format(gap.min(), layer)
        # same chart: interiors must not overlap
        inner = same_chart & (a != b)
        assert not interiors_overlap(tri_uv[a[inner]], tri_uv[b[inner]], 1e-9).any(), (
            "two triangles overlap in layer {}".format(layer))


def check_texels_finite(layout):
    points, normals, geometric = texel_geometry(layout.texels, layout.atlas, layout.mesh)
    assert np.isfinite(points).all() and np.isfinite(normals).all()
    assert np.allclose(np.linalg.norm(normals, axis=1), 1.0)
    uv = layout.atlas.layer_uv()
    assert np.isfinite(uv).all() and uv.min() > 0.0 and uv.max() < 1.0


def overlapping_pairs(mesh, charts, axis, tolerance):
    """Triangle pairs ``(a, b)`` of one chart on ``axis``, of different faces, whose projections overlap where
    their depths differ by more than ``tolerance`` (object units): every pair of each chart whose boxes meet,
    judged by :mod:`plane_judge` on the mesh projected here (the axis coordinate dropped), not by core's own
    projection or tests."""
    live = ~mesh.degenerate
    keep = [k for k in range(3) if k != axis]
    corners = mesh.positions[mesh.triangles]                              # (t, 3, 3)
    uv, depth = corners[:, :, keep], corners[:, :, axis]
    group = np.where(live, charts.chart_of_face[mesh.triangle_face, axis], -1)
    pairs = boxes_within(uv, group, 0.0)
    a, b = pairs[:, 0], pairs[:, 1]
    a, b = a[mesh.triangle_face[a] != mesh.triangle_face[b]], b[mesh.triangle_face[a] != mesh.triangle_face[b]]
    meet = interiors_overlap(uv[a], uv[b], 1e-12 * mesh.scale ** 2)
    a, b = a[meet], b[meet]
    point = overlap_point(uv[a], uv[b])
    gap = np.abs(depth_at(point, uv[a], depth[a]) - depth_at(point, uv[b], depth[b]))
    return a[gap > tolerance], b[gap > tolerance]


def overlaps_per_axis(mesh, topology, charts):
    """Count of triangle pairs of one chart whose projections overlap at different depths, per axis
    (:func:`overlapping_pairs`, beyond the layout's own ``SAME_SURFACE``)."""
    return [len(overlapping_pairs(mesh, charts, axis, SAME_SURFACE * mesh.scale)[0]) for axis in range(3)]


def surface_normals(mesh, topology, rounds=NORMAL_SMOOTHING):
    """Each face's normal averaged, area-weighted, with the faces sharing an edge with it, ``rounds`` times:
    the normal of the surface around the face, which decides the charts it joins (written here on its own)."""
    corner = mesh.positions[mesh.triangles]
    summed = np.zeros((mesh.face_count, 3))
    np.add.at(summed, mesh.triangle_face, np.cross(corner[:, 1] - corner[:, 0], corner[:, 2] - corner[:, 0]))
    a, b = topology.face_edges[:, 0], topology.face_edges[:, 1]
    for _ in range(rounds):
        spread = summed.copy()
        np.add.at(spread, a, summed[b])
        np.add.at(spread, b, summed[a])
        summed = spread
    length = np.linalg.norm(summed, axis=1, keepdims=True)
    return np.where(length > 0, summed / np.where(length > 0, length, 1.0), 0.0)


def check_charts(mesh, compare_angle=60.0):
    """Cluster ``mesh`` and assert every property issue 3 asks of the result."""
    topology = face_adjacency(mesh)
    charts = cluster_faces(mesh, topology, compare_angle)
    live = ~mesh.face_degenerate
    covered = (charts.chart_of_face >= 0).sum(axis=1)
    assert (covered[live] >= 1).all(), "a non-degenerate face is in no chart"
    assert (covered[~live] == 0).all()
    own, around = mesh.face_normal, surface_normals(mesh, topology)
    cos_limit = np.cos(np.radians(compare_angle))
    for axis in range(3):
        column = charts.chart_of_face[:, axis]
        member = column >= 0
        signed = charts.chart_axis[column[member]]
        assert (signed // 2 == axis).all(), "chart stored on the wrong axis"
        facing = (own[member] * AXES[signed]).sum(axis=1)
        assert (facing > 0).all(), "a face sits in a chart of an axis it faces away from"
        within = (around[member] * AXES[signed]).sum(axis=1) >= cos_limit - 1e-9
        dominant = charts.dominant_axis[member] == signed
        assert (within | dominant).all(), "a face whose surface is outside the compare angle joined a chart"
    assert overlaps_per_axis(mesh, topology, charts) == [0, 0, 0], "a chart folds over itself"
    return topology, charts


def chart_kinds(atlas):
    """(c,) int: 0 point, 1 small, 2 large, as the packer classed each chart at the atlas' density."""
    count = len(atlas.chart_texel)
    placed = atlas.member_placed
    chart, uv = atlas.member_chart[placed], atlas.member_uv[placed]          # uv in texels
    low = np.full((count, 2), np.inf)
    high = np.full((count, 2), -np.inf)
    np.minimum.at(low, chart, uv.min(axis=1))
    np.maximum.at(high, chart, uv.max(axis=1))
    extent = np.where(np.isfinite(low), high - low, 0.0)
    # the packer's own rule on the placed extents (texels, so density 1); its points are those it stored as one
    kind = packing_chart_kinds(extent, np.isfinite(low[:, 0]), 1.0).astype(np.int64)
    kind[kind == 0] = 1
    kind[atlas.chart_texel >= 0] = 0
    return kind


def least_gap(layout, kind, largest=16):
    """Fewest texels free between the covered or near texels of two different large charts (None: none
    within ``largest``)."""
    atlas, texels = layout.atlas, layout.texels
    drawn = texels.kind != PADDING
    chart = atlas.member_chart[texels.member[drawn]]
    chart = np.where(kind[chart] == 2, chart, -1)
    border = largest + 1
    label = np.full((texels.height + 2 * border, texels.width + 2 * border), -1, dtype=np.int64)
    xy = texels.xy(drawn)
    label[xy[:, 1] + border, xy[:, 0] + border] = chart
    here = label[border:-border, border:-border]
    for step in range(1, largest + 1):
        for dx in range(-step, step + 1):
            for dy in range(-step, step + 1):
                if max(abs(dx), abs(dy)) != step:
                    continue
                there = label[border + dy:border + dy + texels.height, border + dx:border + dx + texels.width]
                if ((here >= 0) & (there >= 0) & (here != there)).any():
                    return step - 1
    return None
