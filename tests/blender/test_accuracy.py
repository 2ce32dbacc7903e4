"""Issue 6: at default settings the shown AO is within fixed error bounds of the plain many-ray reference
(tests/support/plain_reference.py, no code shared with the bake).

The bounds fail when the blend or the UV mapping is broken (see
test_thresholds_catch_a_broken_blend and ..._broken_uvs).
"""

import bpy
import numpy as np
import pytest

from accuracy import P99_LIMIT, RMSE_LIMIT, errors, reference_ao, shown_seamless, surface_samples
from blender_scenes import sphere_over_plane, suzanne
from package import seamless_ao
from seamless_ao.core.image.shown import bilinear, blended_ao
from seamless_ao.operators.adapters.mesh_data import read_triangles
from blender_checks import image_array, uv_layer_array

POINTS = 1500


@pytest.fixture(scope="module", params=["suzanne", "sphere_over_plane"])
def baked(request):
    """A mesh baked at default settings, with reference AO at random surface points."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    seamless_ao.register()
    try:
        ob = suzanne(1) if request.param == "suzanne" else sphere_over_plane()
        report = seamless_ao.bake([ob])
        mesh, loops = read_triangles(ob.data)
        triangle, bary, normals = surface_samples(mesh, POINTS, seed=11)
        reference = reference_ao(ob, mesh, triangle, bary, normals, rays=2048)
        yield dict(ob=ob, image=bpy.data.images[report.image], loops=loops, triangle=triangle, bary=bary,
                   normals=normals, reference=reference, report=report)
    finally:
        seamless_ao.unregister()


def test_default_bake_is_within_bounds(baked):
    shown = shown_seamless(baked["ob"], baked["image"], baked["loops"], baked["triangle"], baked["bary"],
                           baked["normals"])
    rmse, p99 = errors(shown, baked["reference"])
    print("{}: RMSE {:.4f}, p99 {:.4f}".format(baked["ob"].name, rmse, p99))
    assert rmse <= RMSE_LIMIT and p99 <= P99_LIMIT, (rmse, p99)


def test_thresholds_catch_a_broken_blend_or_uv_mapping(baked):
    """Plausible bugs must fail the bounds: unnormalised weights |n| (the square forgotten),
    a mirrored atlas (U flipped), and every lookup through the wrong chart (U and V swapped)."""
    ob, loops, triangle, bary = baked["ob"], baked["loops"], baked["triangle"], baked["bary"]
    layer_uv = np.stack([np.einsum("kc,kcd->kd", bary, uv_layer_array(ob.data, name)[loops[triangle]])
                         for name in ("AO_X", "AO_Y", "AO_Z")], axis=1)
    image = image_array(baked["image"])
    samples = np.stack([bilinear(image, layer_uv[:, layer]) for layer in range(3)], axis=1)
    unsquared = np.clip((np.abs(baked["normals"]) * samples).sum(axis=1), 0.0, 1.0)
    mirrored = blended_ao(image, layer_uv * [-1.0, 1.0] + [1.0, 0.0], baked["normals"])
    swapped = blended_ao(image, layer_uv[:, :, ::-1], baked["normals"])
    failures = [errors(b, baked["reference"]) for b in (unsquared, mirrored, swapped)]
    for rmse, p99 in failures:
        assert rmse > RMSE_LIMIT or p99 > P99_LIMIT, failures
