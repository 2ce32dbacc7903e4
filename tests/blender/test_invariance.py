"""Issue 27: the same object bakes the same wherever it stands.  Suzanne (her eyes intersect her head, so the
buried-texel pass matters) baked as is, moved, rotated, mirrored (scale -1, not applied) and beside a far
occluder: moved and far are the same image bit for bit, and mirrored is within the rotated bake's noise
(before per-piece sealing with the transform's handedness, a mirrored bake buried nothing: up to 0.17 apart).
With each ray caster that can take these settings: Geometry Nodes, and Cycles (Ray Caster Automatic's choice)."""

import bpy
import numpy as np
import pytest

from accuracy import surface_samples
from blender_checks import image_array, shown_seamless
from blender_scenes import suzanne
from package import seamless_ao
from seamless_ao.core.settings import BakeSettings
from seamless_ao.operators.adapters.mesh_data import read_triangles
from seamless_ao.operators.adapters.session import BakeSession

SETTINGS = dict(image_size=256, rays=32, seed=0)
PLACEMENTS = {
    "as is": {},
    "moved": dict(location=(7.0, -3.0, 2.5)),
    "rotated": dict(rotation_euler=(0.0, 0.0, np.pi / 2)),
    "mirrored": dict(scale=(-1.0, 1.0, 1.0)),
    "beside a far occluder": dict(far_occluder=True),
}


@pytest.fixture(scope="module", params=["GEOMETRY_NODES", "CYCLES"])
def bakes(request):
    """Each placement's image, what it shows at 1,500 visible points of Suzanne (object space), and how many
    texels it found buried inside another piece (her eyes in her head); and the ray caster."""
    results = {"caster": request.param}
    for name, placement in PLACEMENTS.items():
        bpy.ops.wm.read_factory_settings(use_empty=True)
        seamless_ao.register()
        try:
            ob = suzanne(1)
            for key in ("location", "rotation_euler", "scale"):
                if key in placement:
                    setattr(ob, key, placement[key])
            if placement.get("far_occluder"):
                bpy.ops.mesh.primitive_cube_add(size=2.0, location=(60.0, 0.0, 0.0))
            bpy.context.view_layer.update()
            session = BakeSession([ob], BakeSettings(use_scene_occluders=True, ray_caster=request.param,
                                                     **SETTINGS))
            report = session.run()
            image = bpy.data.images[report.image]
            mesh, loops = read_triangles(ob.data)
            triangle, bary, normals = surface_samples(mesh, 1500, seed=3)
            results[name] = (image_array(image).copy(), shown_seamless(ob, image, loops, triangle, bary, normals),
                             int(session.pipeline.result.buried.sum()))
        finally:
            seamless_ao.unregister()
    return results


def test_a_moved_object_and_one_beside_a_far_occluder_bake_the_same_image_bit_for_bit(bakes):
    plain = bakes["as is"][0]
    assert np.array_equal(bakes["moved"][0], plain)
    assert np.array_equal(bakes["beside a far occluder"][0], plain)


def test_a_mirrored_object_finds_the_texels_buried_inside_another_piece(bakes):
    """The layout is in object space, the same for every placement: the same texels lie inside the head."""
    buried = {name: bakes[name][2] for name in PLACEMENTS}
    print(buried)
    assert buried["as is"] > 50
    for name in ("rotated", "mirrored"):
        assert abs(buried[name] - buried["as is"]) <= 0.1 * buried["as is"], buried


def test_a_mirrored_object_bakes_within_the_noise_of_a_rotated_one(bakes):
    """The rotated bake casts other rays at the same surface (world directions turn with it): its difference
    from the plain bake is ray noise.  The mirrored one must differ no more than that: in RMS, and in the
    99.9th percentile of 1,500 points (about the second largest), not the largest, which is one point of
    noise.  With the first padding ring's rays halved (15e8cdd), seeds 0-4 gave the mirrored bake a larger
    single worst point than the rotated one twice (0.0484 against 0.0463, 0.0695 against 0.0641; its next
    largest 0.0329 and 0.0426), at 2/3 of its RMS.  Without sealing in the mirrored bake's handedness
    (faces wound as in object space) its 99.9th percentile was 0.234 and 0.245 against 0.041 and 0.059.
    With the Cycles caster the two differ by the same noise, either way round: over seeds 0-4 the mirrored
    bake's RMS was 0.89-1.04 times the rotated one's and its 99.9th percentile 0.80-1.14 times, so there it
    may be up to 1.25 times (the fault above made it 4 to 6 times)."""
    allowed = 1.0 if bakes["caster"] == "GEOMETRY_NODES" else 1.25
    plain = bakes["as is"][1]
    rotated = bakes["rotated"][1] - plain
    mirrored = bakes["mirrored"][1] - plain
    rms = lambda values: float(np.sqrt(np.mean(values * values)))       # noqa: E731
    worst = lambda values: float(np.quantile(np.abs(values), 0.999))   # noqa: E731
    print("rotated: RMS {:.4f}, p99.9 {:.4f}, max {:.4f}; mirrored: RMS {:.4f}, p99.9 {:.4f}, max {:.4f}".format(
        rms(rotated), worst(rotated), np.abs(rotated).max(), rms(mirrored), worst(mirrored), np.abs(mirrored).max()))
    assert 0.0 < rms(rotated)                                            # the rotated bake did cast other rays
    assert rms(mirrored) <= allowed * rms(rotated)
    assert worst(mirrored) <= allowed * worst(rotated)
