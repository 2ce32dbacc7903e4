"""Lay out, in the current folder, the files the documented headless commands name (run by a real Blender):

    blender --background --factory-startup --python documented_workspace.py

- ``scene.blend``: Suzanne (smooth, with its own UVMap) over a plane named Floor, both selected;
- ``assets/``: a glTF (``with_uv.glb``), an OBJ (``monkey.obj``) and a .blend (``room.blend``, with a text
  block that would write ``asset_ran_code.txt`` if it ever ran);
- ``props/``: two glTF props, one without UVs;
- ``mixed/``: an asset that is not a glTF at all and one with nothing to bake, beside a good one.
"""

import pathlib
import shutil
import sys

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent.parent / "support"))

import bpy  # noqa: E402
import batch_assets  # noqa: E402


def scene_blend(path):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.mesh.primitive_monkey_add(location=(0.0, 0.0, 1.0))
    bpy.ops.object.shade_smooth()
    bpy.ops.mesh.primitive_plane_add(size=6.0)
    bpy.context.active_object.name = "Floor"
    for ob in bpy.context.scene.objects:
        ob.select_set(True)
    bpy.ops.wm.save_as_mainfile(filepath=str(path))


if __name__ == "__main__":
    here = pathlib.Path.cwd()
    folders = {name: here / name for name in ("assets", "props", "mixed")}
    for folder in folders.values():
        folder.mkdir()
    batch_assets.with_uv_glb(folders["assets"] / "with_uv.glb")
    batch_assets.monkey_obj(folders["assets"] / "monkey.obj")
    batch_assets.room_blend(folders["assets"] / "room.blend", here / "asset_ran_code.txt")
    shutil.copy(folders["assets"] / "with_uv.glb", folders["props"] / "crate.glb")
    batch_assets.no_uv_glb(folders["props"] / "cups.glb")
    shutil.copy(folders["assets"] / "monkey.obj", folders["mixed"] / "monkey.obj")
    (folders["mixed"] / "broken.glb").write_bytes(b"glTF\x02\x00\x00\x00 this is not a glTF file at all")
    batch_assets.edges_obj(folders["mixed"] / "edges.obj")
    scene_blend(here / "scene.blend")
