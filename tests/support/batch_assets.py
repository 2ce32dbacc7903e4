"""A folder of generated assets for the batch tests, made with Blender's own exporters.

    make_asset_folder(folder, marker) -> {kind: path}

- ``with_uv.glb``: a box on a floor slab, unwrapped (UVMap), one material shared by both;
- ``no_uv.glb``: an open cylinder and an instance of it (one glTF mesh, two nodes) standing on a
  plate, no UV map, no material;
- ``monkey.obj``: Suzanne on a plate (UVs from the primitive);
- ``room.blend``: a box in a corner, with a text block registered to run on load that
  would write ``marker``: a batch must never run it;
- ``broken.glb``: not a glTF at all;
- ``edges.obj``: only loose edges (nothing to bake).

:func:`uv_cases` writes the glTF assets whose UV maps test the batch's UV policy: stacked islands, tiling
UVs, several materials on one object; :func:`other_formats` writes a small scene as .gltf, .fbx, .ply and
.stl.
"""

import addon_utils
import bpy
import numpy as np


def _scene():
    bpy.ops.wm.read_factory_settings(use_empty=True)


def _plate(size=3.0, z=0.0):
    bpy.ops.mesh.primitive_plane_add(size=size, location=(0.0, 0.0, z))
    return bpy.context.active_object


def _export_glb(path):
    addon_utils.enable("io_scene_gltf2", default_set=False)
    bpy.ops.export_scene.gltf(filepath=str(path), export_format="GLB", use_selection=False)


def with_uv_glb(path):
    _scene()
    bpy.ops.mesh.primitive_cube_add(size=1.0, location=(0.0, 0.0, 0.5))
    box = bpy.context.active_object
    floor = _plate()
    material = bpy.data.materials.new("Painted")
    if bpy.app.version < (5, 0, 0):
        material.use_nodes = True
    for ob in (box, floor):
        ob.data.materials.append(material)
    _export_glb(path)


def no_uv_glb(path):
    _scene()
    bpy.ops.mesh.primitive_cylinder_add(vertices=24, radius=0.5, depth=1.0, location=(0.0, 0.0, 0.5),
                                        end_fill_type="NOTHING")
    cup = bpy.context.active_object
    plate = _plate(size=2.0)
    for ob in (cup, plate):
        while ob.data.uv_layers:
            ob.data.uv_layers.remove(ob.data.uv_layers[0])
    twin = cup.copy()                        # an instance: glTF writes one mesh used by two nodes
    twin.location.x += 1.3
    bpy.context.scene.collection.objects.link(twin)
    _export_glb(path)


def monkey_obj(path):
    _scene()
    bpy.ops.mesh.primitive_monkey_add(location=(0.0, 0.0, 0.8))
    _plate()
    bpy.ops.wm.obj_export(filepath=str(path), export_materials=False)


def room_blend(path, marker):
    _scene()
    bpy.ops.mesh.primitive_cube_add(size=0.6, location=(0.5, 0.5, 0.3))
    _plate(size=2.0)
    bpy.ops.mesh.primitive_plane_add(size=2.0, location=(0.0, 1.0, 1.0), rotation=(1.5708, 0.0, 0.0))
    text = bpy.data.texts.new("on_load.py")
    text.write("import pathlib\npathlib.Path({!r}).write_text('the asset ran code')\n".format(str(marker)))
    text.use_module = True              # "Register": runs on load when auto-run scripts are allowed
    bpy.ops.wm.save_as_mainfile(filepath=str(path))


def stack_blend(path):
    """Suzanne with a live stack (Subdivision, then Bevel) over a plate: the batch bakes what renders."""
    _scene()
    bpy.ops.mesh.primitive_monkey_add(location=(0.0, 0.0, 0.8))
    ob = bpy.context.active_object
    subdivision = ob.modifiers.new("Subdivision", "SUBSURF")
    subdivision.levels = subdivision.render_levels = 1
    ob.modifiers.new("Bevel", "BEVEL").width = 0.02
    _plate()
    bpy.ops.wm.save_as_mainfile(filepath=str(path))


def edges_obj(path):
    lines = ["v 0 0 0", "v 1 0 0", "v 1 1 0", "v 0 1 1", "l 1 2", "l 2 3", "l 3 4"]
    path.write_text("\n".join(lines) + "\n")


def _box_on_a_floor():
    """A box standing on a floor slab, both unwrapped by their primitives."""
    bpy.ops.mesh.primitive_cube_add(size=1.0, location=(0.0, 0.0, 0.5))
    box = bpy.context.active_object
    return box, _plate()


def stacked_uv_glb(path):
    """The box's six faces all on the same UV square (as a texture artist stacks identical sides), and
    Suzanne's mirrored halves on each other: their own UV maps cannot hold AO."""
    _scene()
    box, _ = _box_on_a_floor()
    square = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]
    layer = box.data.uv_layers.active
    for polygon in box.data.polygons:
        for corner, loop in enumerate(polygon.loop_indices):
            layer.data[loop].uv = square[corner % 4]
    bpy.ops.mesh.primitive_monkey_add(location=(1.6, 0.0, 0.7))
    monkey = bpy.context.active_object
    layer = monkey.data.uv_layers.active
    for loop in monkey.data.loops:
        x, _, z = monkey.data.vertices[loop.vertex_index].co
        layer.data[loop.index].uv = (0.5 + 0.35 * abs(x), 0.5 + 0.35 * z)     # each half folded onto the other
    _export_glb(path)


def tiling_uv_glb(path):
    """A floor and a wall with UVs tiling four times (a brick material repeated), and a box standing by them."""
    _scene()
    box, floor = _box_on_a_floor()
    bpy.ops.mesh.primitive_plane_add(size=3.0, location=(0.0, 1.5, 1.5), rotation=(1.5708, 0.0, 0.0))
    wall = bpy.context.active_object
    for ob in (floor, wall):
        layer = ob.data.uv_layers.active
        for loop in ob.data.loops:
            layer.data[loop.index].uv = layer.data[loop.index].uv * 4.0
    _export_glb(path)


def materials_glb(path):
    """One box whose faces carry three materials (the AO image is one, shared by all three), on a floor."""
    _scene()
    box, _ = _box_on_a_floor()
    for name in ("Wood", "Metal", "Paint"):
        material = bpy.data.materials.new(name)
        if bpy.app.version < (5, 0, 0):
            material.use_nodes = True
        box.data.materials.append(material)
    box.data.polygons.foreach_set("material_index", [k % 3 for k in range(len(box.data.polygons))])
    _export_glb(path)


def metal_roughness_glb(path, size=64):
    """A box on a floor, both with a metallic-roughness texture (roughness 0.2 + 0.6 u in G, metallic v in B)
    on their own clean UV maps: the case ORM packing merges the AO into."""
    _scene()
    bpy.ops.mesh.primitive_cube_add(size=1.0, location=(0.0, 0.0, 0.5))
    box = bpy.context.active_object
    floor = _plate()
    texture = bpy.data.images.new("Metal Roughness", size, size, float_buffer=True)
    texture.colorspace_settings.name = "Non-Color"
    u, v = np.meshgrid((np.arange(size) + 0.5) / size, (np.arange(size) + 0.5) / size)
    texels = np.stack([np.ones_like(u), 0.2 + 0.6 * u, v, np.ones_like(u)], axis=-1)
    texture.pixels.foreach_set(texels.astype(np.float32).ravel())
    texture.pack()
    material = bpy.data.materials.new("Textured Metal")
    if bpy.app.version < (5, 0, 0):
        material.use_nodes = True
    nodes, links = material.node_tree.nodes, material.node_tree.links
    principled = next(n for n in nodes if n.bl_idname == "ShaderNodeBsdfPrincipled")
    image_node, split = nodes.new("ShaderNodeTexImage"), nodes.new("ShaderNodeSeparateColor")
    image_node.image = texture
    links.new(image_node.outputs["Color"], split.inputs["Color"])
    links.new(split.outputs["Green"], principled.inputs["Roughness"])
    links.new(split.outputs["Blue"], principled.inputs["Metallic"])
    for ob in (box, floor):
        ob.data.materials.append(material)
    _export_glb(path)
    return texels


def uv_cases(folder):
    """``{kind: path}`` of the assets of :func:`stacked_uv_glb`, :func:`tiling_uv_glb` and :func:`materials_glb`."""
    folder.mkdir(parents=True, exist_ok=True)
    paths = {"stacked": folder / "stacked_uv.glb", "tiling": folder / "tiling_uv.glb",
             "materials": folder / "materials.glb"}
    stacked_uv_glb(paths["stacked"])
    tiling_uv_glb(paths["tiling"])
    materials_glb(paths["materials"])
    _scene()
    return paths


def other_formats(folder):
    """Suzanne over a plate as .gltf (with its .bin), .fbx, .ply and .stl: the other formats a batch reads."""
    folder.mkdir(parents=True, exist_ok=True)
    _scene()
    bpy.ops.mesh.primitive_monkey_add(location=(0.0, 0.0, 0.8))
    _plate()
    addon_utils.enable("io_scene_gltf2", default_set=False)
    addon_utils.enable("io_scene_fbx", default_set=False)
    paths = [folder / name for name in ("scene.gltf", "scene.fbx", "scene_ply.ply", "scene_stl.stl")]
    bpy.ops.export_scene.gltf(filepath=str(paths[0]), export_format="GLTF_SEPARATE")
    bpy.ops.export_scene.fbx(filepath=str(paths[1]))
    bpy.ops.wm.ply_export(filepath=str(paths[2]))
    bpy.ops.wm.stl_export(filepath=str(paths[3]))
    _scene()
    return paths


def make_asset_folder(folder, marker):
    folder.mkdir(parents=True, exist_ok=True)
    paths = {kind: folder / name for kind, name in (
        ("with_uv", "with_uv.glb"), ("no_uv", "no_uv.glb"), ("obj", "monkey.obj"), ("blend", "room.blend"),
        ("broken", "broken.glb"), ("edges", "edges.obj"))}
    with_uv_glb(paths["with_uv"])
    no_uv_glb(paths["no_uv"])
    monkey_obj(paths["obj"])
    room_blend(paths["blend"], marker)
    paths["broken"].write_bytes(b"glTF\x02\x00\x00\x00 this is not a glTF file at all")
    edges_obj(paths["edges"])
    _scene()
    return paths
