"""Benchmark: What a bake adds to the .blend file.

    .venv/5.0/bin/python tests/bench/bench_file_size.py

Saves Blender's Suzanne (``primitive_monkey_add``, a Subdivision modifier of
level 2 applied, smooth shaded) unbaked, then baked at each Quality preset and
at Custom 1024², 16 rays, and saves each uncompressed (Blender's default). Each row:
the AO image's size, its packed bytes (the bake packs it into the file as a
32-bit float OpenEXR), and the file's size against the unbaked file's. Then
Clear: the file saved after Clear against the unbaked one (what a bake leaves
behind once cleared).
"""

import pathlib
import tempfile

from common import finish, markdown_table, say

import bpy
import package

from seamless_ao.core.settings import PRESETS

BAKES = [("Draft", dict(quality="DRAFT")), ("Good (the default)", dict(quality="GOOD")),
         ("Final", dict(quality="FINAL")), ("Custom 1024², 16 rays", dict(quality="CUSTOM", image_size=1024, rays=16))]


def suzanne():
    """A fresh file holding Suzanne, subdivided twice and applied, smooth shaded."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.mesh.primitive_monkey_add()
    ob = bpy.context.active_object
    ob.modifiers.new("Subdivision", "SUBSURF").levels = 2
    bpy.ops.object.modifier_apply(modifier="Subdivision")
    bpy.ops.object.shade_smooth()
    return ob


def saved_bytes(folder, name):
    path = pathlib.Path(folder) / (name + ".blend")
    bpy.ops.wm.save_as_mainfile(filepath=str(path), compress=False, copy=True)
    return path.stat().st_size


def mb(count):
    return "{:.2f} MB".format(count / 1e6)


def main():
    package.seamless_ao.register()
    rows = []
    with tempfile.TemporaryDirectory(prefix="bench_file_size_") as folder:
        suzanne()
        unbaked = saved_bytes(folder, "unbaked")
        for label, settings in BAKES:
            ob = suzanne()
            report = package.seamless_ao.bake([ob], **settings)
            image = bpy.data.images[report.image]
            baked = saved_bytes(folder, "baked")
            rows.append([label, "{}²".format(image.size[0]), mb(image.packed_file.size), mb(baked),
                         "+" + mb(baked - unbaked)])
        package.seamless_ao.clear([ob])
        cleared = saved_bytes(folder, "cleared")
    say("Suzanne, {:,} triangles; the unbaked file: {}.".format(
        sum(len(p.vertices) - 2 for p in ob.data.polygons), mb(unbaked)))
    say()
    say(markdown_table(["bake", "image", "packed image", "file", "added to the file"], rows))
    say()
    say("After Clear (of the last bake): the file is {} ({:+,} bytes against the unbaked file).".format(
        mb(cleared), cleared - unbaked))
    say()
    say("The presets' image sizes: {}.".format(", ".join(
        "{} {}²".format(name.title(), size) for name, (size, _) in PRESETS.items())))


if __name__ == "__main__":
    try:
        main()
    finally:
        finish(__file__, __doc__)
