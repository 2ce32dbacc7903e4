"""`make demo`: bake the built-in demo scene headless and write its outputs.

    .venv/5.0/bin/python operators/launchers/launch.py demo --output-dir out [--rays 64] [--image-size 1024]

Builds the thesis' test scenes (a Cornell box with two blocks, a sphere
hovering over a plane, a subdivided Suzanne), bakes them together into one
shared AO atlas with the public API, and writes:

    out/demo.blend          the scene with UV maps, packed image and materials
    out/demo_ao.png         the AO atlas (16-bit greyscale)
    out/demo_render.png     a Cycles render of the baked result (AO only)
"""

import argparse
import pathlib
import time

import bpy
import numpy as np

from ...core.export.png import encode_png
from ..adapters.exports import image_values
from ..adapters.preview import set_preview
from ..adapters.session import bake
from .demo_scenes import demo_scene


def render(path, samples=32, size=(960, 540)):
    """Cycles render of the scene from a fixed camera, AO shown as emission."""
    scene = bpy.context.scene
    camera = bpy.data.objects.new("Demo Camera", bpy.data.cameras.new("Demo Camera"))
    scene.collection.objects.link(camera)
    camera.location = (0.0, -9.5, 3.2)
    camera.rotation_euler = (np.radians(75.0), 0.0, 0.0)
    camera.data.lens = 35.0
    scene.camera = camera
    scene.world = bpy.data.worlds.new("Black")
    scene.world.color = (0.0, 0.0, 0.0)
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = samples
    scene.render.resolution_x, scene.render.resolution_y = size
    scene.render.resolution_percentage = 100
    scene.view_settings.view_transform = "Standard"
    scene.render.image_settings.file_format = "PNG"
    scene.render.filepath = str(path)
    bpy.ops.render.render(write_still=True)


def main(argv):
    parser = argparse.ArgumentParser(prog="launch.py demo", description=__doc__.splitlines()[0])
    parser.add_argument("--output-dir", default="out")
    parser.add_argument("--rays", type=int, default=64)
    parser.add_argument("--image-size", type=int, default=1024)
    args = parser.parse_args(argv)
    out = pathlib.Path(args.output_dir).resolve()
    out.mkdir(parents=True, exist_ok=True)
    objects = demo_scene()                # the add-on registered by launch.py

    def progress(fraction, message, last=[-1]):
        if int(fraction * 10) != last[0]:
            last[0] = int(fraction * 10)
            print("  {:3.0f}%  {}".format(100 * fraction, message), flush=True)

    print("Baking {} ({} rays per texel, {}² image)".format(
        ", ".join(ob.name for ob in objects), args.rays, args.image_size))
    report = bake(objects, rays=args.rays, image_size=args.image_size, progress=progress)
    print(report.summary())
    print("  stages: " + ", ".join("{} {:.2f} s".format(k, v) for k, v in report.timings.items()))
    image = bpy.data.images[report.image]
    (out / "demo_ao.png").write_bytes(encode_png(image_values(image)[::-1], 16))
    print("Wrote", out / "demo_ao.png")
    set_preview(objects, True)          # render the AO alone
    start = time.perf_counter()
    render(out / "demo_render.png")
    print("Wrote {} (Cycles, {:.1f} s)".format(out / "demo_render.png", time.perf_counter() - start))
    set_preview(objects, False)
    bpy.ops.wm.save_as_mainfile(filepath=str(out / "demo.blend"))
    print("Wrote", out / "demo.blend")
    return 0
