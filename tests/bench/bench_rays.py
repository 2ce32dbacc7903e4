"""Benchmark: Ray casting: rays per second, and a whole 1024² bake.

    .venv/5.0/bin/python tests/bench/bench_rays.py

Strategies, on AO rays of subdivided Suzanne (about 16k triangles):
* Python loop over mathutils BVHTree.ray_cast (one core), directions from numpy;
* Geometry Nodes Raycast node on a point cloud of rays (all cores), the default;
* the full AO path (directions, casting, back-face stepping, sums) with each caster.
Then the time of a whole 1024² bake at 64 rays (issue 9's yardstick; Blender's
own Smart UV Project + Cycles AO bake of that mesh took 1.3 s at 512²/16
samples and 4.2 s at 64 samples on this kind of machine, see report.md for
both measured side by side with their errors).
"""

import sys
import time

import numpy as np

from common import finish, markdown_table, say

import bpy

import package
from blender_scenes import suzanne
from seamless_ao.core.rays.ao import occlusion_sums
from seamless_ao.core.rays.ray_setup import AOParams, BVHCaster, ray_space
from seamless_ao.core.layout import build_layout
from seamless_ao.core.atlas.raster import texel_geometry
from seamless_ao.operators.adapters.mesh_data import read_triangles
from seamless_ao.operators.adapters.casters import NodesCaster


def main():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    package.seamless_ao.register()
    ob = suzanne(2)
    mesh, _ = read_triangles(ob.data)
    centre, to_ray = ray_space(mesh.positions, np.eye(3))
    positions = to_ray(mesh.positions)
    layout = build_layout(mesh, image_size=512)
    texels = np.arange(0, len(layout.texels), max(1, len(layout.texels) // 20000))[:20000]
    points, normals, geometric = texel_geometry(layout.texels, layout.atlas, mesh, texels)
    points, normals = to_ray(points, normals)
    _, geometric = to_ray(points, geometric)
    params = AOParams(rays=64, max_distance=0.5 * mesh.scale, offset=1e-5 * mesh.scale, adaptive=False)
    rows = []
    for name, make in (("mathutils BVHTree.ray_cast loop", BVHCaster), ("Geometry Nodes Raycast", NodesCaster)):
        caster = make(positions, mesh.triangles)
        rng = np.random.default_rng(0)
        count = 200_000 if make is BVHCaster else 2_000_000
        origins = points[rng.integers(0, len(points), count)] + 1e-5 * mesh.scale
        directions = rng.normal(size=(count, 3))
        directions /= np.linalg.norm(directions, axis=1, keepdims=True)
        start = time.perf_counter()
        caster.cast(origins, directions, params.max_distance)
        raw = count / (time.perf_counter() - start)
        start = time.perf_counter()
        subset = slice(0, 3000 if make is BVHCaster else 20000)
        occlusion_sums(points[subset], normals[subset], geometric[subset], layout.texels.index[texels][subset],
                       np.arange(64), params, caster)
        full = len(points[subset]) * 64 / (time.perf_counter() - start)
        rows.append([name, "{:.2f}".format(raw / 1e6), "{:.2f}".format(full / 1e6)])
        caster.free()
        print("measured:", name, file=sys.stderr, flush=True)
    start = time.perf_counter()
    report = package.seamless_ao.bake([ob], image_size=1024, rays=64)
    seconds = time.perf_counter() - start
    say(markdown_table(["strategy", "M rays/s (casting only)", "M rays/s (whole AO path)"], rows))
    say()
    say("1024² bake of subdivided Suzanne ({:,} triangles) at 64 rays: {:.1f} s ({}; {:,} texels, {:,.0f} rays "
          "cast after adaptive stops)".format(len(mesh.triangles), seconds,
                                              ", ".join("{} {:.2f} s".format(k, v) for k, v in report.timings.items()),
                                              report.texels, report.rays))


if __name__ == "__main__":
    main()
    finish(__file__, __doc__)
