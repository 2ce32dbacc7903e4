"""Issue 29: glTF out that is right on every asset.  Each GLB a batch writes passes the Khronos validator, and
read back from the file alone (the occlusion texture's R through its texCoord, as a viewer reads it) shows
the AO of the plain reference on the file's own geometry: clean UVs, no UVs, stacked UVs, tiling UVs, several
materials on one image.  A UV map that cannot hold AO is never used without a warning."""

import pathlib

import bpy
import numpy as np
import pytest

from accuracy import P99_LIMIT, RMSE_LIMIT, errors
from batch_assets import no_uv_glb, uv_cases, with_uv_glb
from gltf_checks import occlusion_images, read_glb, shown_occlusion, validate
from package import seamless_ao
from plain_reference import plain_ao

#: A fixed ray distance, so the reference needs no object's size: every object of an asset sees the others.
REACH = 1.5
SETTINGS = dict(rays=32, image_size=512, texture_size=512, auto_distance=False, max_distance=REACH)


@pytest.fixture(scope="module")
def shipped(tmp_path_factory):
    """Five glTF assets through one batch at its defaults (UV policy auto): ``{kind: (record, output)}``."""
    root = tmp_path_factory.mktemp("gltf")
    folder = root / "assets"
    paths = uv_cases(folder)
    paths["clean"], paths["no_uv"] = folder / "clean.glb", folder / "no_uv.glb"
    with_uv_glb(paths["clean"])
    no_uv_glb(paths["no_uv"])
    bpy.ops.wm.read_factory_settings(use_empty=True)
    records = seamless_ao.batch([str(folder)], output_dir=str(root / "out"), jobs=2, progress=lambda line: None,
                                **SETTINGS)
    by_input = {pathlib.Path(r.input).name: r for r in records}
    shipped = {kind: (by_input[path.name], pathlib.Path(by_input[path.name].output)) for kind, path in paths.items()}
    assert all(record.status == "baked" for record, _ in shipped.values()), [r.error for r in records]
    return shipped


def test_every_glb_passes_the_khronos_validator(shipped):
    reports = validate([output for _, output in shipped.values()])
    for kind, (_, output) in shipped.items():
        report = reports[str(output)]
        assert report["errors"] == 0 and report["warnings"] == 0, (kind, report["messages"])


@pytest.mark.parametrize("kind", ["clean", "no_uv", "stacked", "tiling", "materials"])
def test_read_back_the_occlusion_shows_the_ao_of_the_plain_reference(shipped, kind):
    points, shading, geometric, shown, (positions, triangles) = shown_occlusion(shipped[kind][1])
    reference = plain_ao(positions, triangles, points, shading, geometric, REACH, rays=1024, seed=9)
    rmse, p99 = errors(shown, reference)
    print("{}: RMSE {:.4f}, p99 {:.4f}".format(kind, rmse, p99))
    assert rmse <= RMSE_LIMIT and p99 <= P99_LIMIT, (kind, rmse, p99)


def texcoords(output):
    document, binary = read_glb(output)
    return {texcoord for _, texcoord, _, _ in occlusion_images(document, binary).values()}


def test_a_uv_map_that_cannot_hold_ao_is_replaced_and_the_record_says_why(shipped):
    """Each object whose own map cannot hold the AO (and only those) gets a new one, TEXCOORD_1 beside its own,
    with a warning naming it and the reason; the others keep theirs (texCoord 0)."""
    for kind, reason, unfit in (("stacked", "shares UV space with other faces", {"Cube", "Suzanne"}),
                                ("tiling", "outside the 0-1 square", {"Plane", "Plane.001"})):
        record, output = shipped[kind]
        named = {w.split("'")[1] for w in record.warnings if reason in w and "new UV map AO_UV" in w}
        assert named == unfit, (kind, record.warnings)
        assert texcoords(output) == {0, 1}
    for kind in ("clean", "materials"):
        record, output = shipped[kind]
        assert not any("cannot hold" in warning for warning in record.warnings), record.warnings
        assert texcoords(output) == {0}
    document, _ = read_glb(shipped["materials"][1])
    sources = {document["textures"][m["occlusionTexture"]["index"]]["source"] for m in document["materials"]
               if "occlusionTexture" in m and m["name"] in ("Wood", "Metal", "Paint")}
    assert len(sources) == 1                               # three materials, one AO image


def test_uv_policy_own_keeps_an_unfit_map_only_with_a_warning(shipped, tmp_path):
    stacked = pathlib.Path(shipped["stacked"][0].input)
    records = seamless_ao.batch([str(stacked)], output_dir=str(tmp_path), jobs=1, uv_policy="own",
                                progress=lambda line: None, **SETTINGS)
    assert [r.status for r in records] == ["baked"]
    assert any("cannot hold the AO" in w and "--uv-policy own" in w for w in records[0].warnings), records[0].warnings
    points, shading, geometric, shown, (positions, triangles) = shown_occlusion(records[0].output)
    reference = plain_ao(positions, triangles, points, shading, geometric, REACH, rays=256, seed=9)
    assert errors(shown, reference)[0] > 2 * RMSE_LIMIT            # what the warning is about: the AO is wrong


def test_resample_refuses_an_unfit_map_with_what_is_wrong_unless_told_to_go_on(fresh_scene, addon):
    bpy.ops.mesh.primitive_cube_add()
    box = bpy.context.active_object
    layer = box.data.uv_layers.active
    for loop in box.data.loops:
        layer.data[loop.index].uv = (0.25 + 0.5 * (loop.index % 4 in (1, 2)), 0.25 + 0.5 * (loop.index % 4 > 1))
    addon.bake([box], rays=8, image_size=256)
    with pytest.raises(addon.SeamlessAOError, match="its UV map 'UVMap' cannot hold the AO: 100% of the surface "
                                                    "shares UV space with other faces"):
        addon.resample([box])
    assert addon.resample([box], unfit_uv_map=True) == ["Cube_AO_UVMap"]


@pytest.mark.parametrize("packing, channels", [
    ("ORM", {"occlusion": 0, "roughness": 1, "metallic": 2}),
    ("UNITY_MASK", {"occlusion": 1, "metallic": 0, "smoothness": 3, "detail": 2}),
])
def test_packed_images_carry_each_value_in_its_channel(packing, channels, fresh_scene, addon):
    """Read back from the image: the AO where the packing puts it (the same values as the plain glTF
    image's R), the material's roughness, metallic, smoothness (1 - roughness) in theirs."""
    from blender_checks import image_array
    from blender_scenes import suzanne
    ob = suzanne(1)
    material = bpy.data.materials.new("Rough metal")
    if bpy.app.version < (5, 0, 0):
        material.use_nodes = True
    principled = next(n for n in material.node_tree.nodes if n.bl_idname == "ShaderNodeBsdfPrincipled")
    principled.inputs["Roughness"].default_value, principled.inputs["Metallic"].default_value = 0.3, 0.8
    ob.data.materials.append(material)
    addon.bake([ob], rays=8, image_size=256)
    plain = image_array(bpy.data.images[addon.resample([ob], size=128)[0]]).copy()
    name = addon.resample([ob], size=128, packing=packing, gltf_occlusion=False)[0]
    image = bpy.data.images[name]
    pixels = np.empty(len(image.pixels), dtype=np.float32)
    image.pixels.foreach_get(pixels)
    pixels = pixels.reshape(128, 128, 4)
    assert np.abs(pixels[:, :, channels["occlusion"]] - plain).max() < 1e-6
    expected = {"roughness": 0.3, "metallic": 0.8, "smoothness": 0.7, "detail": 0.0}
    for name, channel in channels.items():
        if name != "occlusion":
            assert np.abs(pixels[:, :, channel] - expected[name]).max() < 1e-6, name
    with pytest.raises(addon.SeamlessAOError, match="Unity mask map carries the AO in G"):
        addon.resample([ob], packing="UNITY_MASK", gltf_occlusion=True)
