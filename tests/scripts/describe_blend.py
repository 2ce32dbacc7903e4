"""What a .blend holds, as one JSON line, for tests that cannot import the Blender that wrote it:

    blender --background --factory-startup --python describe_blend.py -- FILE.blend

``RESULT {"objects": {name: {"uv_maps": [...], "color_attributes": [...], "ao_image": name or null}},
"images": {name: {"packed": bool, "size": [w, h], "finite": bool, "mean": m, "min": a, "max": b}}}``
(pixel figures over the first channel).
"""

import json
import sys

import bpy
import numpy as np

IMAGE_KEY = "seamless_ao_image"     # core/keys.py: on objects, the name of their AO image (read, not imported)


def describe():
    objects = {ob.name: {"uv_maps": [uv.name for uv in ob.data.uv_layers],
                         "color_attributes": [attribute.name for attribute in ob.data.color_attributes],
                         "ao_image": ob.get(IMAGE_KEY)}
               for ob in bpy.data.objects if ob.type == "MESH"}
    images = {}
    for image in bpy.data.images:
        if image.size[0] == 0:
            continue
        pixels = np.empty(image.size[0] * image.size[1] * image.channels, dtype=np.float32)
        image.pixels.foreach_get(pixels)
        first = pixels[::image.channels]
        images[image.name] = {"packed": image.packed_file is not None, "size": list(image.size),
                              "finite": bool(np.isfinite(pixels).all()), "mean": float(first.mean()),
                              "min": float(first.min()), "max": float(first.max())}
    return {"objects": objects, "images": images}


if __name__ == "__main__":
    bpy.ops.wm.open_mainfile(filepath=sys.argv[sys.argv.index("--") + 1], load_ui=False, use_scripts=False)
    print("RESULT " + json.dumps(describe()))
