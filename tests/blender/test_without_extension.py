"""Issue 55: a baked .blend renders its AO in a Blender that does not have the extension (a render farm, a
colleague's machine): the node group, the three UV maps, the packed image and, under a modifier stack that
changes the faces, the stack's Geometry Nodes modifier and its helper meshes are all plain Blender data."""

import json
import subprocess
import sys

import bpy
import numpy as np

from blender_checks import render_emission
from package import seamless_ao

#: Run in a fresh process of the same ``bpy``, which never imports the add-on: open the file, render it as
#: saved, and say which modules of ours were loaded (none may be).
RENDER_WITHOUT = """
import json, sys
import bpy
import numpy as np
bpy.ops.wm.open_mainfile(filepath=sys.argv[1])
scene = bpy.context.scene
scene.render.filepath = sys.argv[2]
bpy.ops.render.render(write_still=True)
image = bpy.data.images.load(sys.argv[2])
width, height = image.size
pixels = np.empty(width * height * 4, dtype=np.float32)
image.pixels.foreach_get(pixels)
ours = sorted(name for name in sys.modules if "seamless" in name.lower())
print(json.dumps({"ours": ours, "addons": sorted(bpy.context.preferences.addons.keys()),
                  "red": pixels.reshape(height, width, 4)[:, :, 0].tolist()}))
"""


def test_a_saved_bake_renders_its_ao_in_a_blender_without_the_extension(addon, fresh_scene, tmp_path):
    bpy.ops.mesh.primitive_monkey_add()
    monkey = bpy.context.active_object
    monkey.modifiers.new("Subdivision", "SUBSURF")        # Blender's default: 1 in the viewport, 2 at render
    bpy.ops.object.shade_smooth()
    seamless_ao.bake([monkey], quality="CUSTOM", image_size=256, rays=16)
    assert monkey.modifiers[-1].type == "NODES"            # the stack route: helper meshes and a GN modifier
    _, here = render_emission(monkey)                      # AO only, as emission, in this process
    blend = tmp_path / "baked.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(blend))
    process = subprocess.run([sys.executable, "-c", RENDER_WITHOUT, str(blend), str(tmp_path / "there.exr")],
                             capture_output=True, text=True, timeout=300)
    assert process.returncode == 0, process.stderr[-3000:]
    there = json.loads(process.stdout.strip().splitlines()[-1])
    assert there["ours"] == [] and not [name for name in there["addons"] if "seamless" in name.lower()]
    there_red = np.array(there["red"], dtype=np.float32)
    on_object = here > 0.0                                 # the world is black
    assert on_object.sum() > 300
    # the AO is there: creases darker than open surface, as in this process's render, pixel for pixel
    assert np.percentile(here[on_object], 10) < 0.7 < np.percentile(here[on_object], 90)
    assert np.abs(there_red - here)[on_object].max() < 0.002, np.abs(there_red - here)[on_object].max()  # same seed
