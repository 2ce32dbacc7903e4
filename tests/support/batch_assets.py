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

:func:`other_formats` writes the same small scene as .gltf, .fbx, .ply and .stl.
"""

import addon_utils
import bpy


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


def edges_obj(path):
    lines = ["v 0 0 0", "v 1 0 0", "v 1 1 0", "v 0 1 1", "l 1 2", "l 2 3", "l 3 4"]
    path.write_text("\n".join(lines) + "\n")


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
