"""Issue 8: the AO out of Blender, as a texture on the user's UV map (glTF) and as colours."""

import json

import bpy
import numpy as np
import pytest

from accuracy import surface_samples
from blender_checks import image_array, uv_layer_array
from blender_scenes import suzanne
from package import run_command, seamless_ao
from seamless_ao.core.image.shown import bilinear
from seamless_ao.core.export.transfer import shown_at
from seamless_ao.operators.adapters.mesh_data import read_triangles
from seamless_ao.shaders.material import enable_nodes


@pytest.fixture
def baked(addon, fresh_scene):
    ob = suzanne(1)
    bpy.context.view_layer.objects.active = ob
    ob.select_set(True)
    seamless_ao.bake([ob], image_size=512, rays=16)
    mesh, loops = read_triangles(ob.data)
    ao = image_array(bpy.data.images[ob["seamless_ao_image"]]).astype(np.float64)
    layer_uv = np.stack([uv_layer_array(ob.data, n)[loops] for n in ("AO_X", "AO_Y", "AO_Z")], axis=1)
    return ob, mesh, loops, ao, layer_uv


def island_interior(mesh, loops, uv, triangle, bary, size, margin=2.0):
    """Points at least ``margin`` texels inside their UV triangle (away from island borders)."""
    corners = uv[loops[triangle]] * size
    point = np.einsum("kc,kcd->kd", bary, corners)
    distance = np.full(len(triangle), np.inf)
    for a, b in ((0, 1), (1, 2), (2, 0)):
        edge = corners[:, b] - corners[:, a]
        length = np.linalg.norm(edge, axis=1)
        cross = np.abs(edge[:, 0] * (point[:, 1] - corners[:, a, 1]) - edge[:, 1] * (point[:, 0] - corners[:, a, 0]))
        distance = np.minimum(distance, cross / np.maximum(length, 1e-12))
    return distance >= margin


def test_resampled_texture_matches_the_blend(baked):
    ob, mesh, loops, ao, layer_uv = baked
    names = seamless_ao.resample([ob], uv_map="UVMap", size=1024)
    image = bpy.data.images[names[0]]
    values = image_array(image).astype(np.float64)
    assert image.packed_file is not None and image.colorspace_settings.name == "Non-Color"
    target = uv_layer_array(ob.data, "UVMap")
    triangle, bary, normals = surface_samples(mesh, 4000, seed=8)
    inside = island_interior(mesh, loops, target, triangle, bary, 1024)
    triangle, bary = triangle[inside], bary[inside]
    looked_up = bilinear(values, np.einsum("kc,kcd->kd", bary, target[loops[triangle]]))
    expected = shown_at(ao, layer_uv, mesh.corner_normals, triangle, bary)
    rmse = np.sqrt(np.mean((looked_up - expected) ** 2))
    assert rmse <= 0.01, rmse


def test_resampled_texture_has_no_empty_texel_in_the_padding(baked):
    from seamless_ao.core.export.transfer import resample_to_uv
    ob, mesh, loops, ao, layer_uv = baked
    target = uv_layer_array(ob.data, "UVMap")[loops]
    values, coverage = resample_to_uv(ao, layer_uv, mesh.corner_normals, target, 256, padding=6)
    assert np.isfinite(values).all()
    assert (coverage <= 2).sum() > 0.3 * coverage.size
    # every texel within 6 rings of an island has a real value, and nothing is black from emptiness
    assert values.min() >= 0.0 and values.max() <= 1.0
    island = coverage <= 1
    grown = island.copy()
    for _ in range(6):
        grown[1:, :] |= grown[:-1, :]
        grown[:-1, :] |= grown[1:, :]
        grown[:, 1:] |= grown[:, :-1]
        grown[:, :-1] |= grown[:, 1:]
    assert (coverage[grown] <= 2).all()


@pytest.mark.parametrize("domain", ["CORNER", "POINT"])
def test_colour_attribute_equals_the_blend_at_the_corners(baked, domain):
    ob, mesh, loops, ao, layer_uv = baked
    seamless_ao.to_color_attribute([ob], domain)
    attribute = ob.data.color_attributes["AO"]
    assert attribute.domain == domain
    colours = np.empty(len(attribute.data) * 4, dtype=np.float32)
    attribute.data.foreach_get("color", colours)
    colours = colours.reshape(-1, 4)[:, 0]
    count = len(loops)
    expected = shown_at(ao, layer_uv, mesh.corner_normals, np.repeat(np.arange(count), 3),
                        np.tile(np.eye(3), (count, 1))).reshape(count, 3)
    if domain == "CORNER":
        assert np.allclose(colours[loops], expected, atol=1e-5)
    else:
        vertex = mesh.triangles
        per_vertex = np.bincount(vertex.ravel(), expected.ravel(), minlength=len(mesh.positions))
        count_per_vertex = np.bincount(vertex.ravel(), minlength=len(mesh.positions))
        # a vertex averages its corners (each loop once: loops shared by triangles of one face count once)
        assert np.abs(colours - np.where(count_per_vertex > 0, per_vertex / np.maximum(count_per_vertex, 1),
                                         1.0)).max() < 0.05


def test_exports_show_the_materials_strength_and_interreflection(baked):
    """Issue 16, item 5: the exports apply each material's node inputs, as the material shows them (the
    render test in test_blender_bake.py checks the shader against the same blend), unless asked not to."""
    from seamless_ao.core.keys import BLEND
    ob, mesh, loops, ao, layer_uv = baked
    node = ob.material_slots[0].material.node_tree.nodes[BLEND]
    node.inputs["Strength"].default_value, node.inputs["Interreflection"].default_value = 0.6, 0.5
    count = len(loops)
    corners = np.repeat(np.arange(count), 3), np.tile(np.eye(3), (count, 1))
    means = {}
    for use, inputs in ((True, (0.6, 0.5)), (False, (1.0, 0.0))):
        seamless_ao.to_color_attribute([ob], "CORNER", material_strength=use)
        colours = np.empty(len(ob.data.loops) * 4, dtype=np.float32)
        ob.data.color_attributes["AO"].data.foreach_get("color", colours)
        expected = shown_at(ao, layer_uv, mesh.corner_normals, *corners, *inputs).reshape(count, 3)
        assert np.allclose(colours.reshape(-1, 4)[loops, 0], expected, atol=1e-5), use
        name, = seamless_ao.resample([ob], size=256, material_strength=use)
        means[use] = image_array(bpy.data.images[name]).mean()
    assert means[True] > means[False] + 0.02, means                   # both inputs lighten the AO


def test_resampled_texture_renders_like_the_node_group(baked):
    """Issue 18, item 5: not the exporter against the function it calls, but two Cycles renders from one
    camera: the material's own Seamless AO output, and the resampled texture through the user's UV map."""
    from blender_checks import render_emission
    ob = baked[0]
    name, = seamless_ao.resample([ob], size=1024)
    _, through_node_group = render_emission(ob)
    material = bpy.data.materials.new("Resampled")
    enable_nodes(material)
    nodes, links = material.node_tree.nodes, material.node_tree.links
    nodes.clear()
    uv, texture = nodes.new("ShaderNodeUVMap"), nodes.new("ShaderNodeTexImage")
    emission, output = nodes.new("ShaderNodeEmission"), nodes.new("ShaderNodeOutputMaterial")
    uv.uv_map, texture.image, texture.interpolation = "UVMap", bpy.data.images[name], "Linear"
    links.new(uv.outputs["UV"], texture.inputs["Vector"])
    links.new(texture.outputs["Color"], emission.inputs["Color"])
    links.new(emission.outputs["Emission"], output.inputs["Surface"])
    ob.material_slots[0].material = material
    _, through_texture = render_emission(ob)
    on_object = (through_node_group > 0.0) & (through_texture > 0.0)      # the world is black
    error = np.abs(through_node_group - through_texture)[on_object]
    assert on_object.sum() > 300
    assert np.median(error) < 0.01 and np.mean(error < 0.03) > 0.9, (np.median(error), np.mean(error < 0.03))


def test_gltf_export_has_the_occlusion_texture(baked, tmp_path):
    ob, *_ = baked
    material = ob.active_material
    seamless_ao.resample([ob], uv_map="UVMap", size=256)
    import addon_utils
    addon_utils.enable("io_scene_gltf2", default_set=False)
    path = tmp_path / "monkey.gltf"
    bpy.ops.export_scene.gltf(filepath=str(path), export_format="GLTF_SEPARATE", use_selection=True)
    data = json.loads(path.read_text())
    exported = next(m for m in data["materials"] if m["name"] == material.name)
    occlusion = exported["occlusionTexture"]
    image = data["images"][data["textures"][occlusion["index"]]["source"]]
    assert image["uri"].startswith("Suzanne_AO_UVMap")
    # texCoord must be the index of UVMap among the exported TEXCOORD sets
    primitive = data["meshes"][0]["primitives"][0]
    texcoords = sorted(k for k in primitive["attributes"] if k.startswith("TEXCOORD_"))
    assert "TEXCOORD_{}".format(occlusion.get("texCoord", 0)) in texcoords
    uv_names = [uv.name for uv in ob.data.uv_layers]
    assert occlusion.get("texCoord", 0) == uv_names.index("UVMap")


def test_clear_removes_exports_too(baked):
    ob, *_ = baked
    seamless_ao.resample([ob], uv_map="UVMap", size=64)
    seamless_ao.to_color_attribute([ob])
    seamless_ao.clear([ob])
    assert "AO" not in ob.data.color_attributes
    assert not [i for i in bpy.data.images if i.name.startswith("Suzanne_AO")]
    assert "glTF Material Output" not in bpy.data.node_groups


def test_export_needs_a_bake_and_an_unwrap(addon, fresh_scene):
    from seamless_ao.core.errors import SeamlessAOError
    ob = suzanne(1)
    with pytest.raises(SeamlessAOError, match="has no Seamless AO bake"):
        seamless_ao.resample([ob])
    seamless_ao.bake([ob], image_size=256, rays=4)
    with pytest.raises(SeamlessAOError, match="no UV map named 'Nope'"):
        seamless_ao.resample([ob], uv_map="Nope")


def test_cli_export(tmp_path, fresh_scene):
    suzanne(1)
    blend = tmp_path / "scene.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(blend))
    for argv in (["bake", "--objects", "Suzanne", "--rays", "4", "--image-size", "256", "--save"],
                 ["export", "--objects", "Suzanne", "--size", "128", "--color-attribute", "CORNER", "--save"]):
        proc = run_command(str(blend), *argv)
        assert proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-2000:]
    bpy.ops.wm.open_mainfile(filepath=str(blend))
    assert "Suzanne_AO_UVMap" in bpy.data.images
    assert "AO" in bpy.data.objects["Suzanne"].data.color_attributes
