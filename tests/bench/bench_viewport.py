"""Benchmark: the AO the viewport shows where its Subdivision level is not the render's.

    .venv/5.0/bin/python tests/bench/bench_viewport.py [--points 1500] [--rays 1024]

Suzanne with a Subdivision modifier, baked at the defaults (the render's level is baked); what the
material shows on the viewport's surface (its own UV maps, each face read through one baked chart,
``core/viewport_uv.py``) at ``--points`` visible points, against the plain reference
(``tests/support/plain_reference.py``, ``--rays`` rays) on the viewport's own surface, and against a
perfect transfer: the plain reference of the render's surface at the nearest points. The last column is
how far apart those two references are: no AO read from the render's surface can come nearer the
viewport's own than that.
"""

import argparse

from common import finish, markdown_table, say

import bpy
import numpy as np

from accuracy import errors, reference_ao
from package import seamless_ao
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
        transfer = reference_ao(ob, rendered, *nearest_on(rendered, points), rays=args.rays)
        rows.append([viewport, render, len(mesh.triangles), len(rendered.triangles),
                     *("{:.4f} / {:.3f}".format(*errors(a, b)) for a, b in
                       ((shown, own), (shown, transfer), (transfer, own)))])
    say("Suzanne, Subdivision at two levels, baked at the defaults; RMSE / 99th percentile of the absolute "
        "error at {} visible points of the viewport's surface, references with {} rays".format(args.points,
                                                                                               args.rays))
    say()
    say(markdown_table(["viewport level", "render level", "viewport triangles", "render triangles",
                        "shown vs viewport's own AO", "shown vs perfect transfer",
                        "perfect transfer vs viewport's own AO"], rows))


if __name__ == "__main__":
    main()
    finish(__file__, __doc__)
