"""EEVEE render of a baked Suzanne's AO-only preview, next to what the blend says, for the tests.

    python eevee_render.py OUT.npz

Runs in its own process because EEVEE needs an OpenGL context, which a
machine without a GPU may or may not provide (Mesa's software renderer
does).  It first renders Blender's default scene with EEVEE: if that fails it prints
``EEVEE unavailable: <reason>`` and exits with 3, and the test is skipped.
Otherwise it prints ``EEVEE available``, bakes, renders, and writes OUT.npz
with ``rendered`` (pixels), ``expected`` (the numpy blend at those pixels).
"""

import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support"))

import bpy  # noqa: E402
import numpy as np  # noqa: E402

import package  # noqa: E402
from blender_checks import eevee_engine, rendered_and_blended  # noqa: E402
from blender_scenes import suzanne  # noqa: E402

SIZE = 96


def eevee_renders():
    """None if EEVEE renders Blender's default scene here (tiny), else why not."""
    bpy.ops.wm.read_factory_settings()
    scene = bpy.context.scene
    scene.render.engine = eevee_engine()
    scene.render.resolution_x = scene.render.resolution_y = 8
    try:
        bpy.ops.render.render()
    except RuntimeError as error:
        return str(error).strip() or "render failed"
    return None


def main(out):
    problem = eevee_renders()
    if problem:
        print("EEVEE unavailable:", problem, flush=True)
        return 3
    print("EEVEE available", flush=True)
    bpy.ops.wm.read_factory_settings(use_empty=True)
    package.seamless_ao.register()
    rendered, expected = rendered_and_blended(suzanne(1), engine=eevee_engine(), size=SIZE)
    np.savez(out, rendered=rendered, expected=expected)
    return 0


if __name__ == "__main__":
    package.hard_exit(main(package.script_arguments()[0]))
