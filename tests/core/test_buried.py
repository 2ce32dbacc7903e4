"""Texels inside another piece (core/mesh/sealed.py, ao.buried_by_vote, job.buried_rim and job.crease_points): found from
their rays, and the rim of a buried region shaded again at the crease."""

import numpy as np

import meshes
from seamless_ao.core.rays.ao import buried_by_vote, occlusion_sums
from seamless_ao.core.rays.job import crease_points
from seamless_ao.core.rays.ray_setup import AOParams, BVHCaster
from seamless_ao.core.rays.targets import buried_rim
from seamless_ao.core.atlas.raster import Texels
from seamless_ao.core.mesh.sealed import MAX_OPENING, sealed_triangles
from seamless_ao.core.mesh.weld import exact_weld


def sheet(size=2.0, z=0.0, rows=4, x=0.0):
    """A flat square sheet at height z centred on (x, 0), facing +Z (rows x rows quads)."""
    s = np.linspace(-0.5 * size, 0.5 * size, rows + 1)
    u, v = np.meshgrid(s, s, indexing="ij")
    positions = np.stack([u.ravel() + x, v.ravel(), np.full(u.size, z)], axis=1)
    return positions, meshes.grid_triangles(rows + 1, rows + 1)


def together(*pieces):
    positions, triangles = [], []
    for p, t in pieces:
        triangles.append(np.asarray(t) + sum(len(q) for q in positions))
        positions.append(p)
    return np.vstack(positions), np.vstack(triangles)


def facing_up(positions, triangles):
    corner = positions[triangles]
    return np.cross(corner[:, 1] - corner[:, 0], corner[:, 2] - corner[:, 0])[:, 2] > 0


def test_exact_weld_joins_exactly_the_vertices_at_the_same_position():
    """The same partition as numpy's unique rows, on coordinates with many repeats and all-zero low bits."""
    rng = np.random.default_rng(1)
    positions = np.round(rng.normal(size=(20000, 3)), 1) * 0.5
    positions[::7] *= -1.0
    positions[::11, 0] = -0.0                                    # -0.0 and 0.0 are one position
    welded = exact_weld(positions)
    _, expected = np.unique(positions + 0.0, axis=0, return_inverse=True)
    pairs = np.unique(np.stack([welded, expected.reshape(-1)], axis=1), axis=0)
    assert len(pairs) == welded.max() + 1 == expected.max() + 1
    again, first = exact_weld(positions, return_first=True)
    assert np.array_equal(again, welded)
    lowest = np.full(welded.max() + 1, len(positions))
    np.minimum.at(lowest, welded, np.arange(len(positions)))
    assert np.array_equal(first, lowest)                          # each index's lowest vertex


def test_a_box_of_six_separate_grids_is_sealed_an_inside_out_box_and_a_sheet_are_not():
    box = meshes.box(subdivisions=3)                           # six grids that share only positions
    assert sealed_triangles(*box).all()
    assert not sealed_triangles(box[0], box[1][:, ::-1]).any()
    positions, triangles = sheet()
    assert facing_up(positions, triangles).all() or (~facing_up(positions, triangles)).all()
    assert not sealed_triangles(positions, triangles).any()
    mixed = together(box, sheet(z=3.0))
    flags = sealed_triangles(*mixed)
    assert flags[:len(box[1])].all() and not flags[len(box[1]):].any()


def opening_of(positions, triangles):
    """|sum of area-weighted normals| / area, computed here on its own (not core's)."""
    corner = positions[triangles]
    cross = np.cross(corner[:, 1] - corner[:, 0], corner[:, 2] - corner[:, 0])
    return np.linalg.norm(cross.sum(axis=0)) / np.linalg.norm(cross, axis=1).sum()


def test_a_shell_with_a_small_hole_and_a_hemisphere_are_sealed_a_shallow_dish_is_not():
    """Sealed means an opening under MAX_OPENING: a sphere with a cap cut off, and a hemisphere (one half),
    are; a shallow dish is not."""
    positions, triangles = meshes.uv_sphere(rings=24, segments=48)
    z = positions[triangles].mean(axis=1)[:, 2]
    capped = triangles[z < 0.9]
    assert opening_of(positions, capped) < 0.1 and sealed_triangles(positions, capped).all()
    hemisphere = triangles[z < 0.0]
    assert abs(opening_of(positions, hemisphere) - 0.5) < 0.02
    assert sealed_triangles(positions, hemisphere).all()
    dish = triangles[z < -0.7]                                      # the cap below z = -0.7
    assert opening_of(positions, dish) > MAX_OPENING
    assert not sealed_triangles(positions, dish).any()


def mirrored(positions, triangles):
    """The mesh mirrored in x, wound so its faces still point outward (what core.rays.ray_setup.world_winding does)."""
    return positions * [-1.0, 1.0, 1.0], triangles[:, [0, 2, 1]]


def test_which_pieces_are_sealed_depends_on_each_piece_alone():
    """An open cup is sealed alone, and stays so whatever else is in the scene (a closed sphere below or above
    it, far away or near), moved, rotated or mirrored; inside out it is not sealed, wherever it stands."""
    positions, triangles = meshes.uv_sphere(rings=24, segments=48)
    z = positions[triangles].mean(axis=1)[:, 2]
    cup = (positions, triangles[z < 0.2])                           # open at the top
    ball = meshes.uv_sphere(radius=0.3, rings=8, segments=16)
    assert sealed_triangles(*cup).all()
    count = len(cup[1])
    for offset in ((0.0, 0.0, -6.0), (0.0, 0.0, 6.0), (40.0, -3.0, 0.5), (0.0, 0.0, -1.5)):
        scene = together(cup, (ball[0] + offset, ball[1]))
        flags = sealed_triangles(*scene)
        assert flags[:count].all() and flags[count:].all(), offset
        inside_out = together((cup[0], cup[1][:, ::-1]), (ball[0] + offset, ball[1]))
        flags = sealed_triangles(*inside_out)
        assert not flags[:count].any() and flags[count:].all(), offset
    turn = np.array([[0.0, -1.0, 0.0], [0.0, 0.0, -1.0], [1.0, 0.0, 0.0]])
    for moved in ((cup[0] + [1e3, -7.0, 2.0], cup[1]), (cup[0] @ turn.T, cup[1]), mirrored(*cup)):
        assert sealed_triangles(*moved).all()
        assert sealed_triangles(*together(moved, (ball[0] - [0.0, 0.0, 6.0], ball[1])))[:count].all()


def behind_counts(points, normals, caster, params):
    texel_ids = np.arange(len(points))
    return occlusion_sums(points, normals, normals, texel_ids, np.arange(params.rays), params, caster)


def test_points_inside_a_closed_piece_are_buried_points_behind_an_open_sheet_are_not():
    box = meshes.box(size=(2.0, 2.0, 2.0), center=(0.0, 0.0, 5.0))
    cover = sheet(size=4.0, z=0.3, x=-4.0)                     # an open sheet over the floor, facing up
    floor = sheet(size=20.0, z=0.0)
    positions, triangles = together(box, cover, floor)
    params = AOParams(rays=32, max_distance=3.0, adaptive=False)
    up = np.tile([0.0, 0.0, 1.0], (3, 1))
    points = np.array([[0.0, 0.0, 4.5],                        # inside the box (facing up, into its top)
                       [-4.0, 0.0, 0.0],                       # on the floor under the sheet
                       [6.0, 6.0, 0.0]])                       # on the floor, out in the open
    caster = BVHCaster(positions, triangles, sealed_triangles(positions, triangles))
    sums, behind = behind_counts(points, up, caster, params)
    assert behind.tolist()[0] == 32 and sums[0] == 32          # every ray meets the inside of the box
    assert behind[1] == 0 and sums[1] > 24                     # the back of the sheet: not sealed, occludes
    assert behind[2] == 0
    assert buried_by_vote(behind, 32, params).tolist() == [True, False, False]
    # a caster told nothing is sealed buries nothing; ignore_backfaces buries nothing
    plain = BVHCaster(positions, triangles)
    assert not buried_by_vote(behind_counts(points, up, plain, params)[1], 32, params).any()
    params.ignore_backfaces = True
    assert not buried_by_vote(behind, 32, params).any()


def test_the_rim_of_a_buried_region_is_its_texels_beside_a_seen_one_of_their_chart():
    """A 6 x 4 image, one chart on columns 0-3, another on 4-5: columns 2-3 of the first are buried."""
    width, height = 6, 4
    index = np.arange(width * height)
    x, row = index % width, index // width
    chart = np.where(x < 4, 0, 1)
    buried_texel = (x >= 2) & (x < 4)
    texels = Texels(width, height, index, np.zeros(len(index), dtype=np.int64), np.zeros(len(index), np.int8))
    computed = np.ones(len(index), dtype=bool)
    rim, neighbour = buried_rim(texels, chart, buried_texel, computed)
    assert np.array_equal(np.sort(rim), np.flatnonzero(x == 2))        # column 3 touches only chart 1
    assert (x[neighbour] == 1).all() and np.array_equal(row[neighbour], row[rim])   # a side before a corner
    assert not len(buried_rim(texels, chart, np.zeros(len(index), bool), computed)[0])


def test_a_crease_point_is_the_last_visible_point_on_the_way_to_the_buried_one():
    """A floor (z = 0, facing up) with a closed box standing in it (x from 1 to 3, z from -1 to 1)."""
    box = meshes.box(size=(2.0, 2.0, 2.0), center=(2.0, 0.0, 0.0))
    positions, triangles = together(box, sheet(size=20.0, z=0.0))
    caster = BVHCaster(positions, triangles)
    params = AOParams(rays=16, max_distance=5.0, offset=1e-4)
    up = np.tile([0.0, 0.0, 1.0], (3, 1))
    near = np.array([[0.6, 0.0, 0.0], [0.9, 0.5, 0.0], [-3.0, 0.0, 0.0]])
    far = np.array([[1.4, 0.0, 0.0], [1.2, 0.5, 0.0], [-2.0, 0.0, 0.0]])     # the third: nothing between
    crease = crease_points(near, up, up, far, params, caster)
    assert np.allclose(crease[:2, 0], 1.0 - params.offset, atol=1e-9)   # just before the box's side
    assert np.allclose(crease[:2, 1], near[:2, 1]) and (crease[:2, 2] > 0).all()    # on the floor's visible side
    assert (crease[:2, 2] <= params.offset).all()
    assert np.allclose(crease[2], near[2] + [0.0, 0.0, params.offset])  # the visible point itself
