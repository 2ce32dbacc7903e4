"""Render a saved .blend from above with Cycles, as a user who opens it would, and keep the pixels:

    blender --background [--factory-startup] FILE.blend --python render_saved.py -- OUT.npy [--without-ao]

With ``--factory-startup`` no extension is enabled: the file must render its AO from its own data (the
image, the UV maps, the node group).  ``--without-ao`` first sets every pixel of every image a bake made
to 1 (no occlusion), for the render to compare against.  Writes the grey values (h, w) float32.
"""

import os
import sys

import bpy
import numpy as np

OURS_KEY = "seamless_ao"          # core/keys.py: on images, made by Seamless AO (read, not imported)
SIZE = 96


def render(path):
    scene = bpy.context.scene
    if "--without-ao" in sys.argv:
        for image in bpy.data.images:
            if image.get(OURS_KEY):
                image.pixels.foreach_set(np.ones(len(image.pixels), dtype=np.float32))
    world = scene.world or bpy.data.worlds.new("Render world")
    scene.world = world
    world.use_nodes = True
    background = next(node for node in world.node_tree.nodes if node.type == "BACKGROUND")
    background.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)   # an even white sky: AO is what shades
    background.inputs["Strength"].default_value = 1.0
    camera = bpy.data.objects.new("Render camera", bpy.data.cameras.new("Render camera"))
    scene.collection.objects.link(camera)
    camera.location = (0.0, -5.0, 6.0)
    camera.rotation_euler = (0.7, 0.0, 0.0)
    scene.camera = camera
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = 32
    scene.cycles.seed = 1
    scene.cycles.use_denoising = False
    scene.render.resolution_x = scene.render.resolution_y = SIZE
    scene.render.resolution_percentage = 100
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.filepath = os.path.join(bpy.app.tempdir, "render.exr")
    bpy.ops.render.render(write_still=True)
    image = bpy.data.images.load(scene.render.filepath)
    pixels = np.empty(len(image.pixels), dtype=np.float32)
    image.pixels.foreach_get(pixels)
    rgba = pixels.reshape(SIZE, SIZE, 4)
    np.save(path, rgba[..., :3].mean(axis=2))


if __name__ == "__main__":
    render(sys.argv[sys.argv.index("--") + 1])
