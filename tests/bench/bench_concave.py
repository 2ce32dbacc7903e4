"""Benchmark: Error along the Cornell box's concave edges, both bakers.

    .venv/5.0/bin/python tests/bench/bench_concave.py

The Cornell box's four clean 90° concave edges (tests/support/blender_scenes.py),
8 points along each, on both faces, at several distances from the edge; what
each baker shows there (Seamless AO: the node group's blend; Cycles: a
bilinear lookup through its Smart UV map) against the plain reference
(tests/support/plain_reference.py, 2048 rays).  Both bakers and the reference
use binary AO within 1.5 units.  A bright line along a corner shows as a
positive mean error at the smallest distances.  Prints one row per baker and
setting: mean error (shown − reference) at each distance, and the RMSE over
all these points.
"""

import numpy as np

from common import finish, markdown_table, say

import bpy

import package
from accuracy import shown_seamless, shown_single_uv
from blender_scenes import cornell_box, cornell_concave_points
from cycles_baseline import UV_NAME, cycles_ao_bake
from plain_reference import locate, plain_ao
from seamless_ao.operators.adapters.mesh_data import read_triangles

DISTANCES = [0.0003, 0.001, 0.003, 0.008, 0.02]
MAX_DISTANCE = 1.5
SEAMLESS_RUNS = [(512, 16), (1024, 32), (1024, 64)]
CYCLES_RUNS = [(512, 16), (512, 64), (1024, 64)]


def main():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    ob = cornell_box()
    mesh, loops = read_triangles(ob.data)
    found = list(cornell_concave_points(DISTANCES))
    points = np.concatenate([f[1] for f in found])
    normals = np.concatenate([f[2] for f in found])
    distance = np.concatenate([f[3] for f in found])
    triangle, bary = locate(mesh.positions, mesh.triangles, points)
    reference = plain_ao(mesh.positions, mesh.triangles, points, normals, normals, MAX_DISTANCE, rays=2048, seed=3)

    def row(method, settings, shown):
        error = shown - reference
        means = ["{:+.3f}".format(float(error[distance == d].mean())) for d in DISTANCES]
        return [method, settings, *means, "{:.3f}".format(float(np.sqrt(np.mean(error**2))))]

    rows = []
    for size, samples in CYCLES_RUNS:
        image = cycles_ao_bake(ob, size, samples, MAX_DISTANCE)[0]
        rows.append(row("Cycles", "{}², {} samples".format(size, samples),
                        shown_single_uv(ob, image, UV_NAME, loops, triangle, bary)))
        bpy.data.images.remove(image)
        print(markdown_table(["method", "settings"], [rows[-1][:2]]).splitlines()[-1], flush=True)
    for size, rays in SEAMLESS_RUNS:
        report = package.seamless_ao.bake([ob], image_size=size, rays=rays, auto_distance=False,
                                          max_distance=MAX_DISTANCE)
        rows.append(row("Seamless AO", "{}², {} rays".format(size, rays),
                        shown_seamless(ob, bpy.data.images[report.image], loops, triangle, bary, normals)))
    say("Cornell box, 4 concave edges x 2 faces x 8 points per distance; mean error (shown - reference) by "
          "distance from the edge, and RMSE over all {} points".format(len(points)))
    say(markdown_table(["method", "settings", *("{} units".format(d) for d in DISTANCES), "RMSE"], rows))


if __name__ == "__main__":
    main()
    finish(__file__, __doc__)
