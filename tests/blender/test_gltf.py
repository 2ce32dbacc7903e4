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
    plain_name = addon.resample([ob], size=128)[0]
    plain = image_array(bpy.data.images[plain_name]).copy()
    name = addon.resample([ob], size=128, packing=packing, gltf_occlusion=False)[0]
    assert name == plain_name and len(bpy.data.images) == 2           # replaced, not piled up (AO image + it)
    pixels = rgba(bpy.data.images[name])
    assert np.abs(pixels[:, :, channels["occlusion"]] - plain).max() == 0.0     # the same 16-bit levels
    expected = {"roughness": 0.3, "metallic": 0.8, "smoothness": 0.7, "detail": 0.0}
    for name, channel in channels.items():
        if name != "occlusion":
            assert np.abs(pixels[:, :, channel] - expected[name]).max() <= 0.5 / 65535 + 1e-7, name
    with pytest.raises(addon.SeamlessAOError, match="Unity Mask Map packing carries the AO in G"):
        addon.resample([ob], packing="UNITY_MASK", gltf_occlusion=True)


def rgba(image):
    """(h, w, 4) float32 pixels of a Blender image, rows bottom up."""
    pixels = np.empty(len(image.pixels), dtype=np.float32)
    image.pixels.foreach_get(pixels)
    return pixels.reshape(image.size[1], image.size[0], 4)


def test_orm_takes_roughness_and_metallic_from_the_materials_texture_on_the_same_uv_map(fresh_scene, addon):
    """A metallic-roughness texture (roughness in G, metallic in B, through Separate Color) read through the UV
    map resampled onto: the ORM image carries its texels, not the Principled inputs' unlinked values.  Read
    through another UV map, it cannot be laid texel for texel, and the inputs' values stand."""
    from blender_scenes import suzanne
    ob = suzanne(1)
    size = 64
    texture = bpy.data.images.new("Metal Roughness", size, size, float_buffer=True)
    texture.colorspace_settings.name = "Non-Color"
    u, v = np.meshgrid((np.arange(size) + 0.5) / size, (np.arange(size) + 0.5) / size)
    texels = np.stack([np.zeros_like(u), u, v * v, np.ones_like(u)], axis=-1)        # rows bottom up, as v
    texture.pixels.foreach_set(texels.astype(np.float32).ravel())
    material = bpy.data.materials.new("Textured")
    if bpy.app.version < (5, 0, 0):
        material.use_nodes = True
    nodes, links = material.node_tree.nodes, material.node_tree.links
    principled = next(n for n in nodes if n.bl_idname == "ShaderNodeBsdfPrincipled")
    principled.inputs["Roughness"].default_value, principled.inputs["Metallic"].default_value = 0.3, 0.8
    image_node, split, uv_node = (nodes.new(kind) for kind in ("ShaderNodeTexImage", "ShaderNodeSeparateColor",
                                                               "ShaderNodeUVMap"))
    image_node.image = texture
    uv_node.uv_map = "UVMap"
    links.new(uv_node.outputs["UV"], image_node.inputs["Vector"])
    links.new(image_node.outputs["Color"], split.inputs["Color"])
    links.new(split.outputs["Green"], principled.inputs["Roughness"])
    links.new(split.outputs["Blue"], principled.inputs["Metallic"])
    ob.data.materials.append(material)
    addon.bake([ob], rays=8, image_size=256)
    pixels = rgba(bpy.data.images[addon.resample([ob], size=size, packing="ORM", gltf_occlusion=False)[0]])
    limit = 0.5 / 65535 + 1e-6
    assert np.abs(pixels[:, :, 1] - texels[:, :, 1]).max() <= limit            # G: roughness, texel for texel
    assert np.abs(pixels[:, :, 2] - texels[:, :, 2]).max() <= limit            # B: metallic
    ob.data.uv_layers.new(name="Second")
    uv_node.uv_map = "Second"
    pixels = rgba(bpy.data.images[addon.resample([ob], size=size, packing="ORM", gltf_occlusion=False)[0]])
    assert np.abs(pixels[:, :, 1] - 0.3).max() <= limit and np.abs(pixels[:, :, 2] - 0.8).max() <= limit


def test_batch_ships_a_greyscale_8_bit_occlusion_texture_that_reads_back_right(shipped, tmp_path):
    """--texture-packing GREY --texture-bit-depth 8: the GLB embeds a one-channel 8-bit PNG, passes the
    validator, and read back through its texCoord shows the AO of the plain reference."""
    from gltf_checks import png_header
    clean = pathlib.Path(shipped["clean"][0].input)
    records = seamless_ao.batch([str(clean)], output_dir=str(tmp_path), jobs=1, texture_packing="GREY",
                                texture_bit_depth="8", progress=lambda line: None, **SETTINGS)
    assert [r.status for r in records] == ["baked"], [r.error for r in records]
    output = records[0].output
    report = validate([output])[str(output)]
    assert report["errors"] == 0 and report["warnings"] == 0, report["messages"]
    document, binary = read_glb(output)
    headers = {png_header(data) for _, _, _, data in occlusion_images(document, binary).values()}
    assert headers == {(512, 512, 8, 1)}
    points, shading, geometric, shown, (positions, triangles) = shown_occlusion(output)
    reference = plain_ao(positions, triangles, points, shading, geometric, REACH, rays=1024, seed=9)
    rmse, p99 = errors(shown, reference)
    assert rmse <= RMSE_LIMIT and p99 <= P99_LIMIT, (rmse, p99)
    with pytest.raises(seamless_ao.SeamlessAOError, match="Unity Mask Map packing carries the AO in G"):
        seamless_ao.batch([str(clean)], output_dir=str(tmp_path), texture_packing="UNITY_MASK")


def test_orm_packing_ships_one_image_as_occlusion_and_metallic_roughness(tmp_path):
    """A batch with ORM packing, on an asset whose materials read a metallic-roughness texture: each
    material's occlusionTexture and metallicRoughnessTexture are one image, whose G and B are the asset's
    roughness and metallic texels and whose R reads back as the AO of the plain reference."""
    from batch_assets import metal_roughness_glb
    from gltf_checks import decode_png
    folder = tmp_path / "assets"
    folder.mkdir()
    metal_roughness_glb(folder / "metal.glb")
    bpy.ops.wm.read_factory_settings(use_empty=True)
    records = seamless_ao.batch([str(folder)], output_dir=str(tmp_path / "out"), jobs=1, texture_packing="ORM",
                                progress=lambda line: None, **SETTINGS)
    assert [r.status for r in records] == ["baked"], [r.error for r in records]
    output = records[0].output
    report = validate([output])[str(output)]
    assert report["errors"] == 0 and report["warnings"] == 0, report["messages"]
    document, binary = read_glb(output)
    textured = [m for m in document["materials"] if "occlusionTexture" in m]
    assert len(textured) == 2                                       # box and floor, each its own copy
    for material in textured:
        occlusion = material["occlusionTexture"]
        metal_rough = material["pbrMetallicRoughness"]["metallicRoughnessTexture"]
        source = {document["textures"][t["index"]]["source"] for t in (occlusion, metal_rough)}
        assert len(source) == 1 and occlusion.get("texCoord", 0) == metal_rough.get("texCoord", 0)
        image = document["images"][source.pop()]
        view = document["bufferViews"][image["bufferView"]]
        pixels = decode_png(binary[view.get("byteOffset", 0):view.get("byteOffset", 0) + view["byteLength"]])
        height, width = pixels.shape[:2]
        u, v = np.meshgrid((np.arange(width) + 0.5) / width, (np.arange(height) + 0.5) / height)
        inner = (u > 1 / 64) & (u < 1 - 1 / 64) & (v > 1 / 64) & (v < 1 - 1 / 64)   # the texture repeats
        assert np.abs(pixels[:, :, 1] - (0.2 + 0.6 * u))[inner].max() < 1e-3       # roughness, from G
        assert np.abs(pixels[:, :, 2] - v)[inner].max() < 1e-3                     # metallic, from B
    points, shading, geometric, shown, (positions, triangles) = shown_occlusion(output)
    reference = plain_ao(positions, triangles, points, shading, geometric, REACH, rays=1024, seed=9)
    rmse, p99 = errors(shown, reference)
    assert rmse <= RMSE_LIMIT and p99 <= P99_LIMIT, (rmse, p99)
