"""core/charts/coarse.py: the charts of a mesh far finer than its image, made on its texel-scale proxy (issue 56)."""

import numpy as np
import pytest

import meshes
from layout_checks import check_lookups, check_texels_finite, overlapping_pairs
from seamless_ao.core.charts.clustering import make_injective, signed_axis_clusters
from seamless_ao.core.charts.coarse import (FINE_PROXY_CELL_TEXELS, FINE_PROXY_FROM_RAYS, PROXY_CELL_TEXELS,
                                            PROXY_FROM_TRIANGLES_PER_TEXEL, proxy_cell_texels, triangles_per_texel)
from seamless_ao.core.layout import build_layout
from seamless_ao.core.mesh.adjacency import face_adjacency
from seamless_ao.core.mesh.triangle_mesh import TriangleMesh
from seamless_ao.core.arrays.graph import connected_components
from seamless_ao.core.mesh.weld import vertex_pieces


def _head_and_eye(gap=0.02):
    """A fine sphere of radius 1 and a fine sphere of radius 0.3 above it, ``gap`` from it: Suzanne's eye in its
    socket, closer to the head than a texel at a small image.  Also each vertex's piece, 0 head, 1 eye."""
    head, head_triangles = meshes.uv_sphere(1.0, rings=60, segments=120)
    eye, eye_triangles = meshes.uv_sphere(0.3, rings=30, segments=60)
    eye = eye + [0.0, 0.0, 1.3 + gap]
    positions = np.vstack([head, eye])
    triangles = np.vstack([head_triangles, eye_triangles + len(head)])
    return TriangleMesh.from_triangles(positions, triangles, smooth=True), np.repeat([0, 1], [len(head), len(eye)])


def _far_overlaps(mesh, charts, density):
    """For each axis, the largest distance in texels between the centres of two triangles of one chart whose
    projections overlap at different depths (0 where none do)."""
    centres = mesh.positions[mesh.triangles].mean(axis=1)
    farthest = []
    for axis in range(3):
        a, b = overlapping_pairs(mesh, charts, axis, 1e-9 * mesh.scale)
        farthest.append(float((np.linalg.norm(centres[a] - centres[b], axis=1) * density).max(initial=0.0)))
    return farthest


def test_pieces_are_triangles_joined_through_corners_at_one_position():
    positions, triangles = meshes.box(subdivisions=3)
    other = positions + [3.0, 0.0, 0.0]
    split_positions, split_triangles = meshes.split_vertices(other, triangles)   # every triangle its own vertices
    mesh = TriangleMesh.from_triangles(np.vstack([positions, split_positions]),
                                       np.vstack([triangles, split_triangles + len(positions)]))
    piece = vertex_pieces(mesh.positions, mesh.triangles)
    assert len(set(piece[:len(positions)].tolist())) == 1
    assert len(set(piece[len(positions):].tolist())) == 1
    assert piece[0] != piece[-1]
    # the same boxes touching, as two meshes put together: two pieces, as the mesh keeps them; one as one mesh
    touching = positions + [1.0, 0.0, 0.0]            # the box spans -0.5..0.5: they share the face x = 0.5
    parts = [TriangleMesh.from_triangles(points, triangles) for points in (positions, touching)]
    together, _ = TriangleMesh.concatenate(parts)
    assert len(set(together.vertex_piece.tolist())) == 2
    assert len(set(vertex_pieces(together.positions, together.triangles).tolist())) == 1


def test_pieces_from_the_islands_a_reader_gives_are_those_of_the_triangles_numbered_alike():
    """Islands (the triangles joined through one vertex index: Blender's Mesh Island) in any numbering, joined
    where vertices share a position: the pieces :func:`vertex_pieces` finds from the triangles, the same
    numbers, with groups too; a vertex in no triangle is a piece of its own, or of the piece at its position."""
    rng = np.random.default_rng(3)
    positions, triangles = meshes.box(subdivisions=3)
    split_positions, split_triangles = meshes.split_vertices(positions + [3.0, 0.0, 0.0], triangles)
    loose = np.array([[9.0, 9.0, 9.0], positions[5]])                  # alone, and at a vertex of the first box
    all_positions = np.vstack([positions, split_positions, loose])
    all_triangles = np.vstack([triangles, split_triangles + len(positions)])
    order = rng.permutation(len(all_positions))                         # vertex order says nothing
    all_positions, all_triangles = all_positions[order], np.argsort(order)[all_triangles]
    by_index = connected_components(len(all_positions), np.vstack([all_triangles[:, :2], all_triangles[:, 1:]]))
    islands = rng.permutation(int(by_index.max()) + 1)[by_index]       # Blender numbers them its own way
    assert int(islands.max()) + 1 > len(split_triangles) + 2            # every split triangle an island at least
    for groups in (None, (all_positions[:, 0] > 1.0).astype(np.int64)):
        expected = vertex_pieces(all_positions, all_triangles, groups)
        assert len(set(expected.tolist())) == 3
        assert np.array_equal(vertex_pieces(all_positions, all_triangles, groups, islands=islands), expected)
    # a mesh given its islands keeps them, and meshes put together number theirs apart
    mesh = TriangleMesh(all_positions, all_triangles, np.arange(len(all_triangles)),
                        np.ones((len(all_triangles), 3, 3)), vertex_island=islands)
    assert np.array_equal(mesh.vertex_piece, vertex_pieces(all_positions, all_triangles))
    together, _ = TriangleMesh.concatenate([mesh, mesh])
    plain, _ = TriangleMesh.concatenate([TriangleMesh(all_positions, all_triangles, mesh.triangle_face,
                                                      mesh.normals_as_read)] * 2)
    assert together.vertex_island is not None and plain.vertex_island is None
    assert np.array_equal(together.vertex_piece, plain.vertex_piece)
    with pytest.raises(ValueError, match="one island per vertex"):
        TriangleMesh(all_positions, all_triangles, mesh.triangle_face, mesh.normals_as_read, vertex_island=islands[1:])


def test_the_proxy_is_finer_for_many_rays_where_the_mesh_is_that_much_finer_still():
    """Few rays (or not known): PROXY_CELL_TEXELS cubes.  From FINE_PROXY_FROM_RAYS rays, FINE_PROXY_CELL_TEXELS
    cubes, but only where the mesh has as many triangles per cube of that size as the proxy's threshold asks of
    the coarser ones; a mesh only just fine enough for a proxy keeps the coarser cubes."""
    mesh, _ = _head_and_eye()
    finer = (PROXY_CELL_TEXELS / FINE_PROXY_CELL_TEXELS) ** 2
    fine_size = next(size for size in (64, 48, 32) if triangles_per_texel(mesh, 60.0, size) >=
                     PROXY_FROM_TRIANGLES_PER_TEXEL * finer)
    coarse_size = next(size for size in range(64, 512, 8)
                       if PROXY_FROM_TRIANGLES_PER_TEXEL <= triangles_per_texel(mesh, 60.0, size) <
                       PROXY_FROM_TRIANGLES_PER_TEXEL * finer)
    assert proxy_cell_texels(mesh, 60.0, None, coarse_size) == PROXY_CELL_TEXELS
    assert proxy_cell_texels(mesh, 60.0, FINE_PROXY_FROM_RAYS, fine_size) == FINE_PROXY_CELL_TEXELS
    assert proxy_cell_texels(mesh, 60.0, FINE_PROXY_FROM_RAYS - 1, fine_size) == PROXY_CELL_TEXELS
    assert proxy_cell_texels(mesh, 60.0, None, fine_size) == PROXY_CELL_TEXELS
    assert proxy_cell_texels(mesh, 60.0, FINE_PROXY_FROM_RAYS, coarse_size) == PROXY_CELL_TEXELS
    # the finer proxy keeps the promises too, and its charts differ from the coarser one's
    fine = build_layout(mesh, image_size=fine_size, rays=FINE_PROXY_FROM_RAYS)
    assert max(_far_overlaps(mesh, fine.charts, fine.atlas.density)) <= 1.5
    check_lookups(fine, np.random.default_rng(1))
    coarse = build_layout(mesh, image_size=fine_size)
    assert not np.array_equal(fine.charts.chart_of_face, coarse.charts.chart_of_face)


def test_a_fine_mesh_at_a_small_image_is_laid_out_on_its_proxy_and_keeps_every_promise():
    mesh, vertex_piece = _head_and_eye()
    assert proxy_cell_texels(mesh, 60.0, image_size=64) == PROXY_CELL_TEXELS
    assert proxy_cell_texels(mesh, 60.0, FINE_PROXY_FROM_RAYS, image_size=512) is None      # laid out whole
    layout = build_layout(mesh, image_size=64)
    charts = layout.charts
    # the eye is closer to the head than a proxy cube, yet no chart holds faces of both
    face_piece = vertex_piece[mesh.triangles[:, 0]]
    for axis in range(3):
        chart = charts.chart_of_face[:, axis]
        inside = chart >= 0
        pieces_per_chart = np.zeros((charts.count, 2), dtype=bool)
        pieces_per_chart[chart[inside], face_piece[inside]] = True
        assert not pieces_per_chart.all(axis=1).any(), axis
    # every face is in a chart on the axis it faces most
    dominant = np.argmax(np.abs(mesh.triangle_normal), axis=1)
    assert (charts.chart_of_face[np.arange(mesh.face_count), dominant] >= 0).all()
    # what the proxy cannot see is folds smaller than its cubes (a texel): none farther apart than that
    assert max(_far_overlaps(mesh, charts, layout.atlas.density)) <= 1.5
    check_lookups(layout, np.random.default_rng(0))
    check_texels_finite(layout)


@pytest.mark.parametrize("same_place_pitches, split", [(0.0, True), (0.4, True), (4.0, False)])
def test_folds_closer_than_same_place_are_left_alone(same_place_pitches, split):
    """The spiral ramp's top folds over itself once a turn, a pitch (0.25) higher, over three turns: its charts
    on Z are split unless ``same_place`` reaches past three pitches (its walls, farther apart, are split
    either way)."""
    pitch = 0.25
    mesh = TriangleMesh.from_triangles(*meshes.spiral_ramp(pitch=pitch))
    topology = face_adjacency(mesh)
    clusters = signed_axis_clusters(mesh, topology)
    charts = make_injective(mesh, topology, clusters, same_place=same_place_pitches * pitch)
    on_z = [int((found.chart_axis // 2 == 2).sum()) for found in (clusters, charts)]
    assert (on_z[1] > on_z[0]) == split, on_z
