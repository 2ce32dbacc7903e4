"""Benchmark: the AO the viewport shows where its Subdivision level is not the render's.

    .venv/5.0/bin/python tests/bench/bench_viewport.py [--points 1500] [--rays 1024]

Suzanne with a Subdivision modifier, baked at the defaults (the render's level is baked); what the
material shows on the viewport's surface at ``--points`` visible points, against the plain reference
(``tests/support/plain_reference.py``, ``--rays`` rays) on the viewport's own surface, and against a
perfect transfer: the plain reference of the render's surface at the nearest points. The next column is
how far apart those two references are: no AO read from the render's surface can come nearer the
viewport's own than that. The standoff column says how far the viewport surface's vertices lie from the
render's surface (``core/viewport_uv.stands_off`` bakes a surface standing off by more than 0.1% too).
At viewport level 1 the viewport's surface reads the render's charts through UV maps of its own
(``core/atlas/viewport_uv.py``); a cage (level 0) stands off the render's surface, and is baked too, in the
same image. The last columns: what the render shows on its own surface against its
plain reference, in that bake and in a bake of the same object with the viewport at the render's level
(nothing more to bake), at ``--points`` visible points of the render's surface.
"""

import argparse

from common import finish, markdown_table, say

import bpy
import numpy as np

from accuracy import errors, reference_ao
from package import seamless_ao
from seamless_ao.core.atlas.viewport_uv import NearestTriangle
from viewport_checks import evaluated_surface, nearest_on, shown_on_the_evaluated_surface

LEVELS = [(1, 2), (0, 3)]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--points", type=int, default=1500)
    parser.add_argument("--rays", type=int, default=1024)
    args = parser.parse_args()
    seamless_ao.register()
    rows = []
    for viewport, render in LEVELS:
        bpy.ops.wm.read_factory_settings(use_empty=True)
        bpy.ops.mesh.primitive_monkey_add()
        ob = bpy.context.active_object
        bpy.ops.object.shade_smooth()
        subdivision = ob.modifiers.new("Subdivision", "SUBSURF")
        subdivision.levels, subdivision.render_levels = viewport, render
        image = bpy.data.images[seamless_ao.bake([ob]).image]
        shown, mesh, triangle, bary, normals = shown_on_the_evaluated_surface(ob, image, count=args.points)
        own = reference_ao(ob, mesh, triangle, bary, normals, rays=args.rays)
        points = np.einsum("kc,kcd->kd", bary, mesh.positions[mesh.triangles[triangle]])
        subdivision.levels = render
        rendered = evaluated_surface(ob)
        # how far the viewport surface's vertices stand off the render's (what core/viewport_uv.stands_off tests)
        offsets = np.linalg.norm(NearestTriangle(rendered.positions, rendered.triangles)(mesh.positions)[1]
                                 - mesh.positions, axis=1)
        standoff = np.percentile(offsets, 90) / np.linalg.norm(np.ptp(rendered.positions, axis=0))
        transfer = reference_ao(ob, rendered, *nearest_on(rendered, points), rays=args.rays)
        at_render = []
        for again in (False, True):
            if again:                                  # the same object baked with nothing more to bake
                image = bpy.data.images[seamless_ao.bake([ob]).image]
            shown_render, render_mesh, *where = shown_on_the_evaluated_surface(ob, image, count=args.points)
            at_render.append(errors(shown_render, reference_ao(ob, render_mesh, *where, rays=args.rays)))
        rows.append([viewport, render, len(mesh.triangles), len(rendered.triangles), "{:.2%}".format(standoff),
                     *("{:.4f} / {:.3f}".format(*errors(a, b)) for a, b in
                       ((shown, own), (shown, transfer), (transfer, own))),
                     *("{:.4f} / {:.3f}".format(*pair) for pair in at_render)])
    say("Suzanne, Subdivision at two levels, baked at the defaults; RMSE / 99th percentile of the absolute "
        "error at {} visible points of each surface, references with {} rays".format(args.points, args.rays))
    say()
    say(markdown_table(["viewport level", "render level", "viewport triangles", "render triangles",
                        "viewport vertices' standoff (90th percentile, share of the diagonal)",
                        "shown vs viewport's own AO", "shown vs perfect transfer",
                        "perfect transfer vs viewport's own AO", "render's surface, this bake",
                        "render's surface, viewport at the render's level"], rows))


if __name__ == "__main__":
    main()
    finish(__file__, __doc__)
