"""The README's first picture: a whole object baked with Seamless AO, as Blender renders it.

    .venv/5.0/bin/python tests/scripts/readme_picture.py [--out docs/images/baked_suzanne.png]

Suzanne with Blender's default Subdivision (1 in the viewport, 2 at render), smooth, baked at the extension's
defaults (Quality Good), then rendered with Cycles (CPU) twice, side by side: the AO alone (Preview AO Only:
the node group's output as emission) and the material with the AO multiplied into its base colour, lit by
a plain grey sky. Writes one PNG.
"""

import argparse
import math
import pathlib
import sys
import tempfile

HERE = pathlib.Path(__file__).resolve()
sys.path.insert(0, str(HERE.parents[1] / "support"))

import bpy  # noqa: E402

from package import seamless_ao  # noqa: E402

ROOT = HERE.parents[2]
WIDTH, HEIGHT = 640, 480


def scene():
    """Suzanne, a camera aimed at it and a grey sky; the baked object."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.mesh.primitive_monkey_add(rotation=(0.0, 0.0, math.radians(25.0)))
    monkey = bpy.context.active_object
    monkey.modifiers.new("Subdivision", "SUBSURF")
    bpy.ops.object.shade_smooth()
    material = bpy.data.materials.new("Suzanne")
    material.use_nodes = True
    material.node_tree.nodes["Principled BSDF"].inputs["Base Color"].default_value = (0.8, 0.62, 0.45, 1.0)
    monkey.data.materials.append(material)
    camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    bpy.context.scene.collection.objects.link(camera)
    camera.location = (0.0, -5.2, 0.4)
    camera.data.lens = 50.0
    aim = camera.constraints.new("TRACK_TO")
    aim.target, aim.track_axis, aim.up_axis = monkey, "TRACK_NEGATIVE_Z", "UP_Y"
    bpy.context.scene.camera = camera
    world = bpy.data.worlds.new("Sky")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.35, 0.37, 0.4, 1.0)
    bpy.context.scene.world = world
    return [monkey]


def render(path, samples=64):
    scene = bpy.context.scene
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = samples
    scene.render.resolution_x, scene.render.resolution_y = WIDTH, HEIGHT
    scene.render.resolution_percentage = 100
    scene.view_settings.view_transform = "Standard"
    scene.render.image_settings.file_format = "PNG"
    scene.render.filepath = str(path)
    bpy.ops.render.render(write_still=True)


def side_by_side(left, right, out):
    """One PNG of two renders of the same size, left and right."""
    images = [bpy.data.images.load(str(path)) for path in (left, right)]
    import numpy as np
    rows = []
    for image in images:
        pixels = np.empty(WIDTH * HEIGHT * 4, dtype=np.float32)
        image.pixels.foreach_get(pixels)
        rows.append(pixels.reshape(HEIGHT, WIDTH, 4))
    joined = np.concatenate(rows, axis=1)
    result = bpy.data.images.new("side_by_side", 2 * WIDTH, HEIGHT)
    result.pixels.foreach_set(joined.ravel())
    result.filepath_raw = str(out)
    result.file_format = "PNG"
    result.save()


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=pathlib.Path, default=ROOT / "docs" / "images" / "baked_suzanne.png")
    args = parser.parse_args(sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else None)
    seamless_ao.register()
    objects = scene()
    report = seamless_ao.bake(objects)
    print(report.summary())
    with tempfile.TemporaryDirectory(prefix="readme_picture_") as scratch:
        shaded, ao_only = pathlib.Path(scratch) / "shaded.png", pathlib.Path(scratch) / "ao.png"
        render(shaded)
        seamless_ao.set_preview(objects, True)
        render(ao_only)
        args.out.parent.mkdir(parents=True, exist_ok=True)
        side_by_side(ao_only, shaded, args.out)
    print("wrote", args.out)


if __name__ == "__main__":
    main()
