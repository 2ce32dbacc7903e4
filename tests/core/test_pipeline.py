"""The whole bake on arrays (core/pipeline.py): meshes and mathutils' BVH in, an image that shows the AO the
plain reference computes out, with no Blender data at all."""

import contextlib

import numpy as np
import pytest

import meshes
from accuracy import P99_LIMIT, RMSE_LIMIT, errors
from plain_reference import plain_ao, visible_points
from whole_texel_caster import WholeTexelCaster
from seamless_ao.core.rays.ao import noise_estimate
from seamless_ao.core.image.shown import blended_ao
from seamless_ao.core.layout import layer_lookup
from seamless_ao.core.mesh.triangle_mesh import TriangleMesh
from seamless_ao.core.pipeline import BakePipeline, bake_arrays
from seamless_ao.core.rays.ray_setup import BVHCaster
from seamless_ao.core.settings import BakeSettings


def ring_on_a_floor():
    """A smooth torus lying on a floor slab, as one mesh of two pieces."""
    ring, ring_triangles = meshes.torus(rings=40, segments=20)
    ring = ring + [0.0, 0.0, 0.36]
    floor, floor_triangles = meshes.box(size=(4.0, 4.0, 0.1), center=(0.0, 0.0, -0.05), subdivisions=4)
    positions = np.vstack([ring, floor])
    triangles = np.vstack([ring_triangles, floor_triangles + len(ring)])
    return TriangleMesh.from_triangles(positions, triangles, smooth=True)


def shown_at_visible_points(result, mesh, count=400):
    """What the node group shows (core/image/shown.py) at random visible points, and those points' normals."""
    triangle, bary, points = visible_points(mesh.positions, mesh.triangles, count, seed=11)
    normals = np.einsum("kc,kcd->kd", bary, mesh.corner_normals[triangle])
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    shown = blended_ao(result.image.astype(np.float64), layer_lookup(result.layout.atlas, mesh, triangle, bary),
                       normals)
    return shown, points, normals, triangle


def test_the_whole_bake_from_arrays_with_mathutils_bvh_shows_the_plain_reference():
    mesh = ring_on_a_floor()
    result = bake_arrays(mesh, rays=32, image_size=256, make_caster=BVHCaster)
    assert result.image.shape == (256, 256) and result.caster == BVHCaster.name
    assert np.isfinite(result.image).all() and 0.0 <= result.image.min() <= result.image.max() <= 1.0
    assert np.isfinite(result.layer_uv).all()
    assert result.texels == int(result.computed.sum()) > 0 and result.rays >= result.texels * 16
    shown, points, normals, triangle = shown_at_visible_points(result, mesh)
    max_distance = 0.5 * float(np.linalg.norm(np.ptp(mesh.positions, axis=0)))
    reference = plain_ao(mesh.positions, mesh.triangles, points, normals, mesh.triangle_normal[triangle],
                         max_distance, rays=1024, seed=5)
    assert reference.min() < 0.6                                       # the ring darkens the floor beneath it
    rmse, p99 = errors(shown, reference)
    assert rmse <= RMSE_LIMIT and p99 <= P99_LIMIT, (rmse, p99)


def test_parts_keep_their_triangles_and_see_what_the_occluders_give():
    """Two meshes baked together: each keeps its own slice of the layout, and the floor is darker under the
    ring only when the occluders the caller read are handed over (the Blender side's scene occluders) and
    the settings ask for them."""
    ring = TriangleMesh.from_triangles(*meshes.torus(rings=32, segments=16), smooth=True)
    floor = TriangleMesh.from_triangles(*meshes.box(size=(4.0, 4.0, 0.1), subdivisions=4))
    lift, drop = np.eye(4), np.eye(4)
    lift[2, 3], drop[2, 3] = 0.36, -0.05
    occluders = [[(other.positions @ matrix[:3, :3].T + matrix[:3, 3], other.triangles)]
                 for other, matrix in ((floor, drop), (ring, lift))]
    settings = BakeSettings(quality="CUSTOM", rays=16, image_size=256, use_scene_occluders=True)
    together = BakePipeline([ring, floor], [lift, drop], settings, BVHCaster, occluders).run()
    alone = BakePipeline([ring, floor], [lift, drop], settings.replace(use_scene_occluders=False), BVHCaster,
                         occluders).run()
    assert together.part_triangles(0) == slice(0, len(ring.triangles))
    assert together.part_triangles(1) == slice(len(ring.triangles), len(ring.triangles) + len(floor.triangles))
    # what the Blender side writes into each part's AO_X/Y/Z: its slice of every triangle's UVs, layer by layer,
    # rounded once to the float32 a UV map holds (and in float64 where asked)
    every = together.layer_uv
    for part in (0, 1):
        for axis, (uv, exact) in enumerate(zip(together.part_axis_uv(part), together.part_axis_uv(part, np.float64))):
            assert uv.dtype == np.float32 and exact.dtype == np.float64
            np.testing.assert_array_equal(exact, every[together.part_triangles(part), axis])
            np.testing.assert_array_equal(uv, every[together.part_triangles(part), axis].astype(np.float32))
    # each layer is made when read and not kept (a writer holds one layer at a time): a read changed by its
    # reader leaves the next read as it was
    layers = together.part_axis_uv(1)
    assert len(layers) == 3 and np.stack(layers).shape == (3, len(floor.triangles), 3, 2)
    layers[2][:] = -1.0
    np.testing.assert_array_equal(layers[2], every[together.part_triangles(1), 2].astype(np.float32))
    with pytest.raises(IndexError):
        layers[3]
    floor_texels = together.layout.part_of_texel() == 1
    under = floor_texels & together.computed
    assert together.texel_ao[under].mean() < alone.texel_ao[under].mean() - 0.02


@pytest.mark.parametrize("rays", [1, 16])
def test_the_noise_reported_is_that_of_two_seeds_apart(rays):
    """The truth: two bakes that differ only in their seed differ by the noise times the square root of 2 at
    every texel. With one ray a texel's own spread says nothing (0 or 1); with 16 stratified rays it says
    more than 1.6 times the truth. Texels side by side see both right, and the adaptive stop, which stops
    nothing up to 16 rays, leaves no texel out."""
    mesh = ring_on_a_floor()
    first, second, still = (bake_arrays(mesh, rays=rays, image_size=256, denoise=False, seed=seed,
                                        adaptive=adaptive, make_caster=BVHCaster)
                            for seed, adaptive in ((1, True), (2, True), (1, False)))
    truth = np.sqrt(np.mean((first.texel_ao.astype(float) - second.texel_ao.astype(float)) ** 2) / 2)
    assert truth > (0.1 if rays == 1 else 0.02)
    assert 0.9 * truth < first.noise < 1.3 * truth, (first.noise, truth)
    assert first.noise == still.noise
    if rays > 1:                                            # what each texel's own rays alone would say
        sampled = first.computed & ~first.buried
        assert noise_estimate(first.texel_ao[sampled], first.ray_count[sampled]) > 1.6 * truth


def test_a_bake_holds_what_it_frees_from_its_first_step_to_its_last(monkeypatch):
    """core/freed_memory.py: the pipeline's steps run within a hold for its triangles, left when it ends."""
    entered, left = [], []

    @contextlib.contextmanager
    def hold(triangles):
        entered.append(triangles)
        yield True
        left.append(triangles)

    monkeypatch.setattr("seamless_ao.core.pipeline.freed_memory_held", hold)
    mesh = TriangleMesh.from_triangles(*meshes.torus(rings=24, segments=12), smooth=True)
    pipeline = BakePipeline([mesh], [np.eye(4)], BakeSettings(rays=4, image_size=128), BVHCaster)
    steps = pipeline.steps()
    next(steps)
    assert entered == [len(mesh.triangles)] and not left
    for _ in steps:
        pass
    assert left == entered and pipeline.result is not None


@pytest.mark.parametrize("make_caster, rays, gives_back", [(BVHCaster, 16, False), (WholeTexelCaster, 4, False),
                                                           (WholeTexelCaster, 16, True)])
def test_freed_memory_goes_back_before_the_rays_only_where_a_caster_bakes_the_bulk(make_caster, rays, gives_back,
                                                                                 monkeypatch):
    """core/freed_memory.py: the layout's freed heap is handed back before the rays where Cycles will bake
    the bulk (its scene comes on top of the pilot's BVH), not where the node casts every ray (at 4 rays the
    pilot's own): the pages would only fault back in."""
    asked = []
    monkeypatch.setattr("seamless_ao.core.pipeline.give_back_freed_memory", asked.append)
    mesh = TriangleMesh.from_triangles(*meshes.torus(rings=24, segments=12), smooth=True)
    bake_arrays(mesh, rays=rays, image_size=256, make_caster=make_caster)
    assert asked == ([len(mesh.triangles)] if gives_back else [])
