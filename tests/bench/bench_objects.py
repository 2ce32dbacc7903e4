"""Benchmark: Many objects baked together into one image.

    .venv/5.0/bin/python tests/bench/bench_objects.py [--objects 1000] [--runs 3] [--bake 400]

``--objects`` boxes of random proportions (48 triangles each), each in its own
object space as Blender hands them over, laid out together at 1024²
(``core.layout.build_layout``).  Prints the median seconds of each stage
over ``--runs`` layouts after an untimed first one.  The objects are
concatenated before clustering (one pass for all), so the per-object Python
overhead of clustering and injectivity is gone.

Then ``--bake`` cubes as Blender objects on a grid, each with its own mesh,
baked together at 512², 16 rays, with Scene Occluders off and on (a batch
turns it on): the whole bake, and where its time goes (one run each after a
warm-up bake of 10 cubes).
"""

import argparse
import statistics
import time

from common import finish, markdown_table, say

import bpy
import numpy as np

import meshes
import package
from seamless_ao.core.mesh.triangle_mesh import TriangleMesh
from seamless_ao.core.layout import build_layout


def boxes(count, seed=0):
    rng = np.random.default_rng(seed)
    return [TriangleMesh.from_triangles(*meshes.box(size=tuple(rng.uniform(0.2, 1.0, 3)), subdivisions=2))
            for _ in range(count)]


def cube_objects(count):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.mesh.primitive_cube_add(size=0.8)
    first = bpy.context.active_object
    objects = [first]
    side = int(count ** 0.5) + 1
    for k in range(1, count):
        copy = first.copy()
        copy.data = first.data.copy()
        copy.location = (k % side, k // side, 0.0)
        bpy.context.scene.collection.objects.link(copy)
        objects.append(copy)
    bpy.context.view_layer.update()
    return objects


def bake_rows(count):
    package.seamless_ao.bake(cube_objects(10), image_size=256, rays=4)           # warm-up
    rows = []
    for occluders in (False, True):
        objects = cube_objects(count)
        start = time.perf_counter()
        report = package.seamless_ao.bake(objects, image_size=512, rays=16, use_scene_occluders=occluders)
        seconds = time.perf_counter() - start
        staged = sum(report.timings.values())
        rows.append([count, "on" if occluders else "off", "{:.2f}".format(seconds),
                     " + ".join("{} {:.2f}".format(k, v) for k, v in report.timings.items()),
                     "{:.2f}".format(seconds - staged)])
    return rows


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--objects", type=int, default=1000)
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--bake", type=int, default=400, help="cube objects to bake (0: skip)")
    args = parser.parse_args(package.script_arguments())
    parts = boxes(args.objects)
    build_layout(parts, image_size=1024)
    runs = []
    for _ in range(args.runs):
        start = time.perf_counter()
        layout = build_layout(parts, image_size=1024)
        runs.append(dict(layout.timings, total=time.perf_counter() - start))
    stages = list(runs[0])
    say("{} objects, {} triangles, 1024², median of {} runs (seconds)".format(
        len(parts), sum(len(p.triangles) for p in parts), args.runs))
    say(markdown_table(stages, [["{:.3f}".format(statistics.median(r[s] for r in runs)) for s in stages]]))
    if args.bake:
        say()
        say("{} cubes as objects, baked together at 512², 16 rays (seconds)".format(args.bake))
        say(markdown_table(["objects", "scene occluders", "bake s", "stages s", "rest s (read, casters, write)"],
                             bake_rows(args.bake)))


if __name__ == "__main__":
    main()
    finish(__file__, __doc__)
